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

sample=$source/data/sample
"$consumer" "$sample/gbuffer.exr" "$sample/scene.json" "$sample/camera.json" "$work/library.exr"
"$prefix/bin/decalcomp" composite "$sample/gbuffer.exr" --decals "$sample/scene.json" \
  --camera "$sample/camera.json" --device cpu -o "$work/cli.exr" > "$work/cli.log"
cmp "$work/library.exr" "$work/cli.exr"
echo "install ($mode): the consumer's output is the CLI's, byte for byte"
