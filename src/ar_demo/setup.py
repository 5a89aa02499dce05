# catkin_python_setup() installs the ar_demo Python package; not for pip.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["ar_demo"], package_dir={"": "src"}))
