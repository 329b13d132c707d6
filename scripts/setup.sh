#!/usr/bin/env bash
# Installs every Debian package endovascular_sim needs (idempotent, as root),
# then the Python packages Debian lacks (requirements.txt, pinned) into the
# project's virtual environment build/venv (scripts/python.sh runs it).
# Usage: scripts/setup.sh
set -euo pipefail

packages=(
  # toolchain and core library
  build-essential cmake pkg-config
  libeigen3-dev libsuitesparse-dev libyaml-cpp-dev
  liburdfdom-dev liburdfdom-headers-dev libconsole-bridge-dev libtinyxml-dev
  libgtest-dev googletest libgmock-dev libbenchmark-dev libcli11-dev
  # JSON lines (evsim run --json, navigate), escaped whatever their strings hold
  nlohmann-json3-dev
  # patient centrelines and ParaView output (VTK), and the example's generator
  libvtk9-dev python3-vtk9
  # virtual fluoroscopy: X-ray cross sections (xraylib), ROS image transport
  libxrl-dev libimage-transport-dev
  # ROS 1 from Debian: catkin, roscpp, message generation and definitions
  catkin python3-catkin-pkg python3-empy
  ros-message-generation ros-message-runtime python3-genmsg python3-gencpp
  libroscpp-dev rosout python3-roslaunch python3-rostest python3-rostopic
  librostest-dev
  ros-std-msgs libstd-msgs-dev ros-geometry-msgs libgeometry-msgs-dev
  ros-nav-msgs libnav-msgs-dev ros-sensor-msgs libsensor-msgs-dev
  ros-visualization-msgs libvisualization-msgs-dev
  ros-std-srvs libstd-srvs-dev
  libtf2-ros-dev libtf2-dev libtf2-msgs-dev ros-tf2-msgs
  ros-diagnostic-msgs libdiagnostic-msgs-dev libros-rosgraph-msgs-dev python3-rosgraph-msgs
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libactionlib-dev libactionlib-msgs-dev ros-actionlib-msgs
  # Python side of the rostests (message bindings, rosservice, rosnode)
  python3-genpy python3-std-msgs python3-geometry-msgs python3-nav-msgs
  python3-sensor-msgs python3-visualization-msgs python3-std-srvs
  python3-diagnostic-msgs python3-tf2-ros python3-rosservice python3-rosnode rosbash
  python3-actionlib python3-actionlib-msgs
  # rviz, and a virtual display to screenshot it
  rviz xvfb xauth libgl1-mesa-dri imagemagick
  # plots and pictures
  python3-matplotlib python3-numpy
  # the Python front: pybind11 and the module's build, its tests, and what
  # Gymnasium and Stable-Baselines3 need from Debian (requirements.txt: the rest)
  pybind11-dev python3-dev python3-venv python3-pytest python3-yaml
  python3-torch python3-pandas python3-cloudpickle python3-typing-extensions
  # batches on a cluster: Dask's scheduler and workers
  python3-dask python3-distributed
  # independent LCP oracle for the contact tests
  libsiconos-numerics-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} Debian packages present"
fi

# The virtual environment: Debian's Python with Debian's packages visible,
# and the pinned PyPI packages of requirements.txt.
repo=$(cd "$(dirname "$0")/.." && pwd)
venv="$repo/build/venv"
if [ ! -x "$venv/bin/python" ]; then
  echo "setup: creating the virtual environment $venv"
  mkdir -p "$repo/build"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
wanted=$(grep -vE '^\s*(#|$)' "$repo/requirements.txt" | tr "A-Z_" "a-z-" | sort)
have=$("$venv/bin/python" -m pip freeze --local 2>/dev/null | tr "A-Z_" "a-z-" | sort)
if [ -n "$(comm -23 <(echo "$wanted") <(echo "$have"))" ]; then
  echo "setup: installing the pinned Python packages of requirements.txt"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-deps \
    -r "$repo/requirements.txt"
else
  echo "setup: the pinned Python packages are present"
fi
