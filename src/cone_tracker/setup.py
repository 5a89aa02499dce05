# Installs cone_tracker's Python module (catkin_python_setup): evaluate_detections' scoring and figures.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["cone_tracker"], package_dir={"": "src"}))
