# Installs rig_model's Python module (catkin_python_setup); not for use with pip.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["rig_model"], package_dir={"": "src"}))
