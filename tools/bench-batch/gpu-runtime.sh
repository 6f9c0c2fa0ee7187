#!/bin/sh
# Builds a small, self-contained runtime for tools/bench-batch/run.sh on a remote GPU host that
# cannot install anything and takes at most 64 MiB of carried files: the full `ldd` closure of
# decalcomp is ~350 MB, because OpenImageIO 2.4 (linked with BIND_NOW) has DT_NEEDED on plugin
# libraries we never use (OpenCV, DCMTK, FFmpeg, libheif, OpenVDB, LibRaw), which pull in GDAL,
# x265, ICU and so on.
#
#   sh tools/bench-batch/gpu-runtime.sh OUT_DIR        (e.g. .gpu-batch)
#
# Into OUT_DIR it writes:
#   bin/   stripped decalcomp, decalcomp-gbuffer-gen, decalcomp-bench-batch, decalcomp-images.so
#          (from $BIN, default build/) and oiiotool (from /usr/bin; `openimageio-tools` is installed if missing);
#   lib/   every shared library those need, except glibc's own, libstdc++, libgcc_s and
#          libOpenCL.so.1 (the host's are used). The heavy plugin libraries ($STUBS) are replaced
#          by generated stubs: same SONAME, every dynamic symbol the real library defines with the
#          same version, binding and type; functions trap (ud2, like __builtin_trap()), data
#          objects are zero-filled objects of the real size; no dependencies at all. So the
#          closure stops at them. A stub leaves out symbols that a real library of the runtime
#          (or glibc/libstdc++/libgcc_s) also defines (inline and template instantiations in
#          C++ libraries), so that a stub earlier in the search order never interposes a
#          working definition with a trap. NOTYPE and absolute symbols are left out.
#   runtime.tar.xz   bin/ and lib/ (xz -9): the only thing that must travel, with
#   unpack.sh        which, on the host, unpacks it to /tmp/rt (or $1) and prints the
#                    LD_LIBRARY_PATH to use.
#   .gitignore       "*", so that OUT_DIR is ignored by git (carry it explicitly).
# bin/ and lib/ are removed after packing unless KEEP_UNPACKED=1.
#
# Environment: BIN (binaries, default build/ of this checkout), OIIOTOOL_SRC (default
# /usr/bin/oiiotool), STUBS (sonames to stub, space-separated), KEEP_UNPACKED.
set -eu

OUT=${1:?usage: gpu-runtime.sh OUT_DIR}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BIN:-$ROOT/build}
OIIOTOOL_SRC=${OIIOTOOL_SRC:-/usr/bin/oiiotool}
# Not stubbed, because they run at start-up or on every image open (a stub traps there):
# DCMTK (OpenImageIO's static initialisers construct dcmimage's DiRegister, and dcmimage's call
# OFLog::getLogger) and LibRaw (OpenImageIO calls libraw_version() when it catalogues its
# plugins, on the first ImageInput). libxml2 (needed by dcmdata only) is stubbed instead: it
# pulls in ICU (~35 MB).
STUBS=${STUBS:-"libopencv_core.so.406 libopencv_imgproc.so.406 libopencv_videoio.so.406
  libavcodec.so.59 libavformat.so.59 libavutil.so.57 libswscale.so.6
  libheif.so.1 libopenvdb.so.10.0 libxml2.so.2"}
# Provided by the host (newer and compatible, or the driver's ICD loader).
HOSTLIBS="ld-linux-x86-64.so.2 libc.so.6 libm.so.6 libmvec.so.1 libpthread.so.0 libdl.so.2
  librt.so.1 libresolv.so.2 libutil.so.1 libstdc++.so.6 libgcc_s.so.1 libOpenCL.so.1"

if [ ! -x "$OIIOTOOL_SRC" ]; then
  echo "installing openimageio-tools for $OIIOTOOL_SRC" >&2
  sudo apt-get install -y openimageio-tools >&2
fi
for t in readelf strip gcc tar xz ldconfig; do
  command -v "$t" > /dev/null || { echo "gpu-runtime.sh: $t is missing" >&2; exit 1; }
done

mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
[ "$OUT" != / ] || { echo "gpu-runtime.sh: refusing OUT_DIR /" >&2; exit 1; }
rm -rf "${OUT:?}/bin" "${OUT:?}/lib" "$OUT/runtime.tar.xz"
mkdir -p "$OUT/bin" "$OUT/lib"
printf '*\n' > "$OUT/.gitignore"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/gpu-runtime.XXXXXX")
trap 'rm -rf "$TMP"' EXIT INT TERM

# resolve SONAME: path of the x86-64 library the dynamic linker would pick here.
resolve() {
  p=$(ldconfig -p | awk -v n="$1" '$1 == n && /x86-64/ {print $NF; exit}')
  if [ -z "$p" ]; then
    for d in /lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu /lib /usr/lib /usr/local/lib; do
      [ -e "$d/$1" ] && { p=$d/$1; break; }
    done
  fi
  [ -n "$p" ] || { echo "gpu-runtime.sh: cannot find $1" >&2; exit 1; }
  echo "$p"
}
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'; }
# shellcheck disable=SC2086,SC2116 # the list is word-split on purpose (newlines to spaces)
inlist() { case " $(echo $2) " in *" $1 "*) return 0 ;; esac; return 1; }
# defined dynamic symbols of a file: "name version bind type size" (version "-" if none,
# "@name" for a non-default version); NOTYPE and absolute symbols left out.
defsyms() {
  readelf --dyn-syms -W "$1" | awk '
    function num(s,   i, v, c) {
      if (s !~ /^0x/) return s + 0
      v = 0
      for (i = 3; i <= length(s); i++) { c = index("0123456789abcdef", tolower(substr(s, i, 1))) - 1; v = v * 16 + c }
      return v
    }
    $1 ~ /^[0-9]+:$/ && NF >= 8 && $7 != "UND" && $7 != "ABS" && $4 != "NOTYPE" && $4 != "SECTION" && $4 != "FILE" {
      name = $8; ver = "-"
      if ((i = index(name, "@@")) > 0) { ver = substr(name, i + 2); name = substr(name, 1, i - 1) }
      else if ((i = index(name, "@")) > 0) { ver = "@" substr(name, i + 1); name = substr(name, 1, i - 1) }
      print name, ver, $5, $4, num($3)
    }'
}

# 1. binaries
# decalcomp-images.so, OpenImageIO's module, goes beside the CLI, where the CLI looks for it first.
for b in decalcomp decalcomp-gbuffer-gen decalcomp-bench-batch decalcomp-images.so; do
  [ -f "$BIN/$b" ] || { echo "gpu-runtime.sh: $BIN/$b is missing (set BIN)" >&2; exit 1; }
  cp "$BIN/$b" "$OUT/bin/$b"
done
cp "$OIIOTOOL_SRC" "$OUT/bin/oiiotool"
strip --strip-all "$OUT"/bin/*

# 2. closure of the real libraries, stopping at host libraries and stubs
: > "$TMP/real"   # "soname path"
: > "$TMP/stubs"  # sonames met that get a stub
: > "$TMP/queue"
for f in "$OUT"/bin/*; do echo "$f" >> "$TMP/queue"; done
while [ -s "$TMP/queue" ]; do
  f=$(head -n 1 "$TMP/queue")
  sed -i 1d "$TMP/queue"
  for n in $(needed "$f"); do
    if inlist "$n" "$HOSTLIBS"; then continue; fi
    if inlist "$n" "$STUBS"; then
      grep -qxF "$n" "$TMP/stubs" || echo "$n" >> "$TMP/stubs"
      continue
    fi
    if ! awk -v n="$n" '$1 == n {f = 1} END {exit !f}' "$TMP/real"; then
      p=$(resolve "$n")
      echo "$n $p" >> "$TMP/real"
      echo "$p" >> "$TMP/queue"
    fi
  done
done
while read -r n p; do
  cp -L "$p" "$OUT/lib/$n"
  chmod u+w "$OUT/lib/$n"
  strip --strip-unneeded "$OUT/lib/$n"
done < "$TMP/real"

# 3. names defined by everything real that is loaded with the stubs: a stub must not define them
{
  for f in "$OUT"/bin/* "$OUT"/lib/*; do defsyms "$f"; done
  for n in $HOSTLIBS; do p=$(resolve "$n" 2> /dev/null) && defsyms "$p"; done
} | awk '{print $1}' | sort -u > "$TMP/taken"

# 4. stubs
while read -r n; do
  p=$(resolve "$n")
  defsyms "$p" | awk 'NR == FNR {taken[$1] = 1; next} !($1 in taken)' "$TMP/taken" - > "$TMP/syms"
  awk -v soname="$n" '
    BEGIN { print "\t.section .note.GNU-stack,\"\",@progbits" }
    {
      name = $1; ver = $2; bind = $3; type = $4; size = $5
      sym = name
      if (ver ~ /^@/) {  # non-default version: define an alias, export it only as name@VER
        sym = "__stub_" NR
        printf "\t.globl %s\n\t.symver %s, %s%s, remove\n", sym, sym, name, ver
        hidden[substr(ver, 2)] = 1
      } else if (ver != "-") {
        nodes[ver] = nodes[ver] "\t\t\"" name "\";\n"
      }
      if (sym == name) {
        if (bind == "WEAK") printf "\t.weak \"%s\"\n", sym
        else printf "\t.globl \"%s\"\n", sym
      }
      if (type == "FUNC" || type == "IFUNC") {
        printf "\t.text\n\t.type \"%s\", @function\n\"%s\":\n\tud2\n\t.size \"%s\", 2\n", sym, sym, sym
      } else {
        if (type == "TLS") { sec = ".tbss"; t = "@tls_object"; flags = ",\"awT\",@nobits" }
        else { sec = ".bss"; t = (bind == "UNIQUE") ? "@gnu_unique_object" : "@object"; flags = "" }
        printf "\t.section %s%s\n\t.balign %d\n\t.type \"%s\", %s\n\"%s\":\n\t.zero %d\n\t.size \"%s\", %d\n",
          sec, flags, (size >= 16 ? 16 : 8), sym, t, sym, (size > 0 ? size : 1), sym, size
      }
    }
    END {
      map = FILENAME ".map"; loc = 0
      for (v in hidden) { loc = 1; if (!(v in nodes)) nodes[v] = "" }
      for (v in nodes) {
        printf "%s {\n", v > map
        if (nodes[v] != "") printf "\tglobal:\n%s", nodes[v] > map
        if (loc) { printf "\tlocal:\n\t\t__stub_*;\n" > map; loc = 0 }
        print "};" > map
      }
    }' "$TMP/syms" > "$TMP/stub.s"
  set -- -shared -nostdlib -Wl,-soname,"$n" -Wl,-z,noexecstack
  if [ -s "$TMP/syms.map" ]; then set -- "$@" -Wl,--version-script="$TMP/syms.map"; fi
  gcc "$@" -o "$OUT/lib/$n" "$TMP/stub.s"
  strip --strip-unneeded "$OUT/lib/$n"
  echo "stub $n: $(wc -l < "$TMP/syms") of $(defsyms "$p" | wc -l) symbols ($(($(stat -c %s "$OUT/lib/$n") / 1024)) KiB; real $(($(stat -L -c %s "$p") / 1024)) KiB)" >&2
  rm -f "$TMP/syms.map"
done < "$TMP/stubs"

# 5. pack
tar -C "$OUT" -cf - bin lib | xz -9 > "$OUT/runtime.tar.xz"
cat > "$OUT/unpack.sh" << 'EOF'
#!/bin/sh
# Unpacks runtime.tar.xz (next to this script; made by tools/bench-batch/gpu-runtime.sh) into
# ${1:-/tmp/rt} and prints how to run tools/bench-batch/run.sh with it.
set -eu
HERE=$(cd "$(dirname "$0")" && pwd)
RT=${1:-/tmp/rt}
rm -rf "$RT"
mkdir -p "$RT"
if command -v xz > /dev/null; then
  xz -dc "$HERE/runtime.tar.xz" | tar -C "$RT" -xf -
else
  python3 -c 'import sys, tarfile; tarfile.open(sys.argv[1], "r:xz").extractall(sys.argv[2])' "$HERE/runtime.tar.xz" "$RT"
fi
echo "unpacked to $RT ($(du -sh "$RT" | cut -f1)); use:" >&2
echo "export LD_LIBRARY_PATH=$RT/lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}" >&2
echo "BIN=$RT/bin OIIOTOOL=$RT/bin/oiiotool sh tools/bench-batch/run.sh ..." >&2
echo "$RT/lib"
EOF
chmod +x "$OUT/unpack.sh"
echo "real libraries: $(wc -l < "$TMP/real"); stubs: $(tr '\n' ' ' < "$TMP/stubs")" >&2
echo "bin $(du -sk "$OUT/bin" | cut -f1) KiB, lib $(du -sk "$OUT/lib" | cut -f1) KiB unpacked" >&2
echo "$OUT/runtime.tar.xz: $(stat -c %s "$OUT/runtime.tar.xz") bytes ($(du -h "$OUT/runtime.tar.xz" | cut -f1))" >&2
if [ "${KEEP_UNPACKED:-0}" != 1 ]; then rm -rf "${OUT:?}/bin" "${OUT:?}/lib"; fi
