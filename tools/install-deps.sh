#!/bin/sh
# Installs decalcomp's build and test dependencies from Debian 12's packages.
# Idempotent and non-interactive; skips apt-get entirely when everything is present.
set -eu
# The last line is the sanitizer and fuzzing build (tools/sanitize-and-fuzz.sh): clang-15 with
# libFuzzer and its OpenMP runtime, and llvm-15 for llvm-symbolizer (readable sanitizer traces).
PACKAGES="build-essential cmake ninja-build pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers clinfo clang
  libopenexr-dev libopenimageio-dev openimageio-tools libglm-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev
  libtinyobjloader-dev libdeflate-dev zlib1g-dev lld
  pybind11-dev python3-dev python3-numpy python3-pytest python3-openimageio python3-venv python3-pip help2man bash-completion libopencolorio-dev
  slurm-wlm slurmctld slurmd slurm-client munge
  clang-15 libfuzzer-15-dev libomp-15-dev llvm-15"
missing=""
for p in $PACKAGES; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -z "$missing" ]; then
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "installing:$missing"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends $missing
