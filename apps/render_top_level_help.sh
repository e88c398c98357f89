#!/usr/bin/env bash
# render_top_level_help.sh FULL_PROGRAM OUTPUT: writes FULL_PROGRAM's `--help` as a C++ raw string
# literal for the launcher (launcher.cpp), with the placeholders of command_programs.h for the
# program name and the machine-dependent memory default. Nothing is written when it fails.
set -euo pipefail
program=${1:?usage: render_top_level_help.sh FULL_PROGRAM OUTPUT}
output=${2:?usage: render_top_level_help.sh FULL_PROGRAM OUTPUT}
help="$output.help.tmp"
# In a sanitizer build this run is part of the build, not a test: a leak report at exit must not
# fail it (the tests run the same program with leak checking on).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
SKELGRASP_HELP_TEMPLATE=1 bash -c 'exec -a @SKELGRASP_PROGRAM@ "$0" --help' "$program" > "$help"
if grep -q ')skelgrasp_help"' "$help"; then
  echo "render_top_level_help.sh: the help text contains the raw-string delimiter" >&2
  exit 1
fi
{ printf 'R"skelgrasp_help('; cat "$help"; printf ')skelgrasp_help"\n'; } > "$output.tmp"
rm -f "$help"
mv "$output.tmp" "$output"
