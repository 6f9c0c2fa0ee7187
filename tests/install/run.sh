#!/bin/bash
# The installed tree as a studio would use it (ctest "Install.*"; docs/library.md):
#   run.sh BUILD_DIR SOURCE_DIR WORK_DIR MODE     MODE: cmake | cmake-static | pkg-config
# installs BUILD_DIR into WORK_DIR/prefix, builds tests/install/consumer against it (CMake
# package or pkg-config), runs it on data/sample and checks that the output matches the CLI's.
set -euo pipefail
build=$1 source=$2 work=$3 mode=$4
rm -rf "$work" && mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log"

# Only the public headers: internal ones (json_fields.hpp, reference.hpp...) stay in the tree.
for internal in json_fields reference synth temporary_files; do
  if [ -e "$prefix/include/decalcomp/$internal.hpp" ]; then
    echo "internal header installed: include/decalcomp/$internal.hpp" >&2; exit 1
  fi
done

# The manual page documents every subcommand; the completion completes them and their options.
man=$prefix/share/man/man1/decalcomp.1
for section in "DECALCOMP COMPOSITE" "DECALCOMP BATCH" "DECALCOMP INFO" "DECALCOMP DEVICES"; do
  grep -q "^\.SH \"$section\"" "$man" || { echo "$man: no section $section" >&2; exit 1; }
done
grep -q -- "--decals" "$man" || { echo "$man: composite's options missing" >&2; exit 1; }
completion=$prefix/share/bash-completion/completions/decalcomp
words=$(bash -c \
  'source "$1"; COMP_WORDS=("${@:2}"); COMP_CWORD=3; _decalcomp; echo "${COMPREPLY[*]}"' _ "$completion" \
  "$prefix/bin/decalcomp" composite in.exr --dec)
[ "$words" = "--decals" ] || { echo "$completion: 'composite --dec' completes to '$words'" >&2; exit 1; }

libdir=$(cd "$prefix" && find . -name 'libdecalcomp.so' -printf '%h\n' | head -1)
case $mode in
  cmake|cmake-static)
    static=OFF; [ "$mode" = cmake-static ] && static=ON
    cmake -S "$source/tests/install/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCONSUMER_STATIC=$static -DCONSUMER_HEADER_CHECKS=$([ $static = ON ] && echo OFF || echo ON) -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
    cmake --build "$work/consumer" -j2 > "$work/build.log"
    consumer=$work/consumer/consumer ;;
  pkg-config)
    export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig"
    # shellcheck disable=SC2046
    c++ -std=c++20 -O1 "$source/tests/install/consumer/main.cpp" -o "$work/consumer-pc" \
      $(pkg-config --cflags --libs decalcomp) -Wl,-rpath,"$prefix/$libdir"
    consumer=$work/consumer-pc ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac

# OpenImageIO's module (the sample's textures need it) comes from the installed tree, not the build
# tree: the CLI and libdecalcomp.so find it relative to themselves; a program linking the static
# library finds it at the configured install path or, installed elsewhere as here, is told.
module=$(cd "$prefix" && pwd -P)/${libdir#./}/decalcomp/decalcomp-images.so
[ -f "$module" ] || { echo "$module: not installed" >&2; exit 1; }
[ "$mode" = cmake-static ] && export DECALCOMP_IMAGE_MODULE="$module"
sample=$source/data/sample
LD_DEBUG=files "$consumer" "$sample/gbuffer.exr" "$sample/scene.json" "$sample/camera.json" "$work/library.exr" \
  2> "$work/library.ld"
LD_DEBUG=files "$prefix/bin/decalcomp" composite "$sample/gbuffer.exr" --decals "$sample/scene.json" \
  --camera "$sample/camera.json" --device cpu -o "$work/cli.exr" > "$work/cli.log" 2> "$work/cli.ld"
for log in "$work/library.ld" "$work/cli.ld"; do
  grep -q "$module" "$log" || { echo "$log: the image module was not loaded from $module" >&2; exit 1; }
  if grep -q "$(cd "$build" && pwd -P)/decalcomp-images.so" "$log"; then
    echo "$log: the build tree's image module was loaded" >&2; exit 1
  fi
done
cmp "$work/library.exr" "$work/cli.exr"
echo "install ($mode): the consumer's output is the CLI's, byte for byte"
