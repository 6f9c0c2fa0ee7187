#!/bin/sh
# decalcomp.1 from the program's own help (help2man), with each subcommand's --help as a section
# of its own, so the manual says exactly what the CLI does.   tools/make-man.sh DECALCOMP OUT.1
set -eu
program=$1
out=$2
include=$(mktemp)
trap 'rm -f "$include"' EXIT
for sub in $("$program" --help | sed -n '/^Subcommands:/,$ s/^  \([a-z][a-z-]*\) .*/\1/p'); do
  printf '[decalcomp %s]\n.nf\n' "$sub" >>"$include"
  # roff: backslashes written as \e, lines starting with . or ' protected by \&.
  "$program" "$sub" --help | sed -e "s|$program|decalcomp|g" -e 's/\\/\\e/g' -e "s/^\([.']\)/\\\\\&\1/" >>"$include"
  printf '.fi\n\n' >>"$include"
done
printf '[see also]\nThe documentation in the source tree: README.md, docs/cli.md, docs/scene-format.md,\ndocs/profiles.md, docs/library.md, docs/python.md.\n' >>"$include"
help2man --no-info --section=1 --name="composite decals into rendered G-buffer EXRs on OpenCL devices" \
  --include="$include" --output="$out" "$program"
