#!/usr/bin/env bash
# Installs the Debian 12 packages pgt needs, only those that are missing (apt-get update once).
set -euo pipefail
packages=(
  cmake g++ make
  libembree-dev libopenimageio-dev openimageio-tools libosd-dev libglm-dev libopenexr-dev
  libtbb-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev libcli11-dev libtinyobjloader-dev
  libpng-dev libtiff-dev libfreetype-dev fonts-dejavu-core
  libboost-dev  # header-only Boost.Math: Student's t in pgt compare
  clang-format clang libclang-rt-14-dev
  libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  glslang-dev glslang-tools spirv-tools libspirv-cross-c-shared-dev  # HLSL -> SPIR-V -> GLSL; glslang-dev's CMake package names /usr/bin/glslangValidator
  libtinygltf-dev assimp-testmodels  # glTF 2.0 bases; real and broken glTF assets for the tests
  python3-numpy python3-matplotlib python3-pandas python3-openimageio
  python3-dev pybind11-dev python3-pybind11 python3-pytest  # the Python module and its tests
  dpkg-dev file  # cpack -G DEB: dpkg-shlibdeps finds the .deb's dependencies, CPackDeb runs `file`
  slurmctld slurmd slurm-client munge  # studies on a cluster; the distributed ctest
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "installing: ${missing[*]}"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi
