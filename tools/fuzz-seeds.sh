#!/bin/bash
# Collects the fuzz targets' seed corpora from data/ (docs/fuzzing.md "Targets and seeds"):
#   tools/fuzz-seeds.sh BUILD_DIR OUT_DIR
# writes OUT_DIR/<target>/ for every target. Scenes, cameras and profiles are copied; textures
# larger than 16 KB and the G-buffers are cut down with oiiotool (small inputs run fast and
# libFuzzer sizes its inputs after the largest seed), the G-buffers in several compressions and
# layouts, plus a few tiny synthetic frames from BUILD_DIR's decalcomp-gbuffer-gen (multi-part,
# header camera, overscan, every naming). The checked-in tests/fuzz/seeds/ are added by the runner.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: tools/fuzz-seeds.sh BUILD_DIR OUT_DIR}
out=${2:?usage: tools/fuzz-seeds.sh BUILD_DIR OUT_DIR}
rm -rf "$out"
mkdir -p "$out"/{scene,camera,profile,cryptomatte,texture,exr}

# A file under data/ as a flat seed name: data/blender/scene.json -> blender_scene.json
flat() { local rel=${1#data/}; echo "${rel//\//_}"; }

for f in data/*/scene.json data/*/decals.json data/*/boxes.json; do
  [ -f "$f" ] && cp "$f" "$out/scene/$(flat "$f")"
done
for f in data/*/camera.json; do cp "$f" "$out/camera/$(flat "$f")"; done
for f in src/io/profiles/*.json; do cp "$f" "$out/profile/"; done

# Textures: every decal image in data/ (not the frames), large ones resized to 16 texels high.
while IFS= read -r f; do
  name=$(flat "$f")
  if [ "$(stat -c %s "$f")" -le 16384 ]; then
    cp "$f" "$out/texture/$name"
  else
    oiiotool "$f" --resize 0x16 -o "$out/texture/small_$name"
  fi
done < <(find data -type f \( -name '*.png' -o -name '*.exr' \) ! -name 'gbuffer*' ! -name 'truth*' | sort)

# G-buffers: 16x16 cuts in the file's own compression, other compressions, tiled, half, and a
# crop that keeps the full display window (data window inside it).
for f in data/*/gbuffer.exr; do
  name=$(flat "${f%.exr}")
  size=$(oiiotool --info "$f" | sed -n 's/.* \([0-9]*\) x \([0-9]*\),.*/\1 \2/p' | head -1)
  read -r width height <<<"$size"
  at="+$((width / 2 - 8))+$((height / 2 - 8))"
  oiiotool "$f" --cut "16x16$at" -o "$out/exr/${name}_cut.exr"
  oiiotool "$f" --cut "16x16$at" --compression piz -o "$out/exr/${name}_piz.exr"
  oiiotool "$f" --cut "16x16$at" --compression zips -o "$out/exr/${name}_zips.exr"
  oiiotool "$f" --cut "16x16$at" --compression rle --tile 8 8 -o "$out/exr/${name}_tiled_rle.exr"
  oiiotool "$f" --cut "16x16$at" -d half --compression dwaa -o "$out/exr/${name}_half_dwaa.exr"
  oiiotool "$f" --crop "16x16$at" --compression none -o "$out/exr/${name}_crop_raw.exr"
  # The Cryptomatte manifests of the header, with a layer and a few name patterns.
  iinfo -v "$f" | sed -n 's/.*cryptomatte\/[0-9a-f]*\/manifest: "\(.*\)"$/\1/p' | sed 's/\\"/"/g' |
    while IFS= read -r manifest; do
      i=$((${i:-0} + 1))
      printf '%s\nCryptoObject\nWall*\nBox\n' "$manifest" >"$out/cryptomatte/${name}_objects_$i.txt"
      printf '%s\nViewLayer.CryptoMaterial\nM_*\n[BS]*\n?all\n' "$manifest" >"$out/cryptomatte/${name}_materials_$i.txt"
    done
done

gen="$build/decalcomp-gbuffer-gen"
tiny() {
  [ -x "$gen" ] || { echo "fuzz-seeds: no $gen, synthetic seed $1 left out" >&2; return 0; }
  "$gen" --width 8 --height 6 --no-position --camera "$out/exr/.camera.json" -o "$out/exr/$1.exr" "${@:2}" >/dev/null
}
tiny gen_generic --naming generic
tiny gen_generic_multipart --naming generic --multipart
tiny gen_karma_half --naming karma --half --compression piz
tiny gen_renderman_header_camera --naming renderman --header-camera
tiny gen_unreal_ndc --naming unreal --depth ndc --reversed-z
tiny gen_blender_overscan --naming blender --data-window=-2,-1,9,7 --compression none
tiny gen_blender_ortho --naming blender --ortho 2 --depth radial
rm -f "$out/exr/.camera.json"

for t in "$out"/*/; do echo "seeds: $(basename "$t"): $(ls "$t" | wc -l) files, $(du -sk "$t" | cut -f1) KB"; done
