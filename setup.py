# The Python package endovascular_sim (python/endovascular_sim/) for catkin:
# its devel space makes `import endovascular_sim` find these sources beside
# the compiled core (_core) and the generated messages (msg/, srv/).
# Not for pip: scripts/python.sh runs the Python that has it.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(
    packages=["endovascular_sim", "endovascular_sim.envs", "endovascular_sim.batch"],
    package_dir={"": "python"},
))
