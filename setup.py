# The Python package `hope` (src/hope): the bindings' module _hope (built by CMake) and the
# generated messages (hope.msg) join it. Used by catkin_python_setup(); not for pip.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["hope"], package_dir={"": "src"}))
