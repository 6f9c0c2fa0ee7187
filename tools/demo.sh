#!/bin/sh
# Installs the dependencies (Debian 12), builds decalcomp and composites the sample data:
# writes out/*.exr and out/*.png (input albedo | composited albedo).
set -eu
cd "$(dirname "$0")/.."
sh tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$(nproc)" --target decalcomp
mkdir -p out
./build/decalcomp devices
if [ -f data/sample/gbuffer.exr ]; then
  ./build/decalcomp composite data/sample/gbuffer.exr --decals data/sample/scene.json \
    --camera data/sample/camera.json -o out/sample.exr --preview out/sample.png
fi
./build/decalcomp composite data/blender/gbuffer.exr --decals data/blender/scene.json \
  --camera data/blender/camera.json -o out/blender.exr --preview out/blender.png
./build/decalcomp composite data/blender-kinds/gbuffer.exr --decals data/blender-kinds/scene.json \
  --camera data/blender-kinds/camera.json -o out/blender-kinds.exr --preview out/blender-kinds.png
echo "wrote: $(ls out/*.exr out/*.png | tr '\n' ' ')"
