#!/usr/bin/env bash
# `lgh bench gpu` on a lent machine with a GPU (the session's device tool), from a release `lgh`
# built here and carried there, with Vulkan's loader carried as a Debian package. Prints the
# bench's JSON (and writes it to $OUT/gpu.json there), to record with
# `tools/figures take gpu.json CORES CPU ID ...`.
#
# Here, once (x86-64):
#   cargo build --release -p lgh-cli && mkdir -p .dev && objcopy --strip-debug target/release/lgh .dev/lgh
#   echo /.dev/ >> .git/info/exclude; echo /.gl/ >> .git/info/exclude; mkdir -p .gl /tmp/amd64/partial
#   o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
#   apt-get $o update && (cd .gl && apt-get $o download libvulkan1 libglvnd0 libegl1 libgl1 libglx0 libopengl0 libgles2)
# (NVIDIA's Vulkan driver there is libGLX_nvidia, which needs glvnd's libraries.)
# There (carry .dev and .gl): tools/gpu/device.sh [lgh bench gpu's flags]
set -euo pipefail
cd "$(dirname "$0")/../.."
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
nvidia=/usr/local/nvidia/share
if [ -f "$nvidia/vulkan/icd.d/nvidia_icd.json" ]; then
    export VK_DRIVER_FILES="$nvidia/vulkan/icd.d/nvidia_icd.json"
    export __EGL_VENDOR_LIBRARY_FILENAMES="$nvidia/glvnd/egl_vendor.d/10_nvidia.json"
fi
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader >&2 || true
echo "cores: $(nproc); $(grep -m1 'model name' /proc/cpuinfo)" >&2
.dev/lgh bench gpu "$@" --out "${OUT:-/tmp}/gpu.json"
