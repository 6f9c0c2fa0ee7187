#!/bin/bash
# The bench's output_hash column (the GPU machine's only way to compare outputs): the same for
# binned and unbinned shading and for either clean-depth path, which give identical planes, and
# different for another decal count.
set -euo pipefail
bench=$1
hashes() { "$bench" --device cpu --sizes 320x180 --modes both --repeat 1 --no-transfers --csv - "$@" 2>/dev/null |
    awk -F, 'NR > 1 { print $NF }'; }
filtered=$(hashes --counts 16 --pixel-filter blackman-harris:3:fast)
scans=$(hashes --counts 16 --pixel-filter blackman-harris:3:fast --clean-depths plane)
other=$(hashes --counts 17 --pixel-filter blackman-harris:3:fast)
echo "16 decals: $(echo $filtered); with the clean-depth plane: $(echo $scans); 17 decals: $(echo $other)"
[ "$(echo "$filtered" | wc -l)" = 2 ] || { echo "expected a binned and an unbinned row"; exit 1; }
[ "$(echo "$filtered" | sort -u | wc -l)" = 1 ] || { echo "binned and unbinned hashes differ"; exit 1; }
[[ "$(echo "$filtered" | head -1)" =~ ^[0-9a-f]{16}$ ]] || { echo "not a 64-bit hex hash"; exit 1; }
[ "$filtered" = "$scans" ] || { echo "the clean-depth plane changed the hash"; exit 1; }
[ "$(echo "$filtered" | head -1)" != "$(echo "$other" | head -1)" ] || { echo "17 decals hash like 16"; exit 1; }
echo ok
