#!/bin/bash
# Renders our own Blender truth datasets (data/README.md "Our own renders") from scratch and
# measures the 4x-supersampled estimate of the two antialiased ones. Blender 3.4.1 (Debian),
# Cycles on the CPU, fixed seed 0: the same files on every run on the same Blender build.
#   bash tools/blender/make_datasets.sh [gauss] [box] [beauty]     (default: all three)
set -euo pipefail
cd "$(dirname "$0")/../.."
which=("$@")
[ ${#which[@]} -eq 0 ] && which=(gauss box beauty)
render() { nice blender -b --factory-startup --python tools/blender/own_scene.py -- "$@" >/dev/null; }
for w in "${which[@]}"; do
    case "$w" in
    gauss)  # Cycles' Gaussian, Filter Size 2.5 px
        render --out data/blender-aa-gauss --filter gaussian --filter-width 2.5 --samples 256
        /usr/bin/python3 tools/blender/estimate_4x.py data/blender-aa-gauss ;;
    box)    # Cycles' Box, Filter Size 1.0 px
        render --out data/blender-aa-box --filter box --filter-width 1.0 --samples 256
        /usr/bin/python3 tools/blender/estimate_4x.py data/blender-aa-box ;;
    beauty) # Blender's default pixel filter (Blackman-Harris 1.5 px), light passes, direct light only
        render --out data/blender-beauty-aa --filter blackman-harris --filter-width 1.5 --samples 128 \
            --light-passes --no-crypto
        # truth.exr keeps what scoring needs (beside the gbuffer it stays under 6 MB): Combined,
        # DiffCol, DiffDir (to show how the divided light changes at mixed pixels), the masks, Depth
        t=data/blender-beauty-aa/truth.exr
        oiiotool "$t" --ch "$(printf 'ViewLayer.%s,' Combined.R Combined.G Combined.B Combined.A DecalMask.X \
            DecalMaskBox.X DecalMaskFrustum.X Depth.Z DiffCol.R DiffCol.G DiffCol.B DiffDir.R DiffDir.G \
            DiffDir.B | sed 's/,$//')" -d float --compression zip -o "$t.tmp.exr"
        mv "$t.tmp.exr" "$t" ;;
    *) echo "unknown dataset $w" >&2; exit 2 ;;
    esac
done
