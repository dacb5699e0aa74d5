#!/usr/bin/env bash
# Builds the OpenDRIVE parser fuzzer with clang's libFuzzer and AddressSanitizer and runs it for a
# few seconds on a copy of the seed corpus: the shipped maps, plus the third-party .xodr files of
# $FLEET_TEST_DATA (default OPENDRIVE_DIR) where that folder exists. Exit status 0: no crash found.
# Usage:
#   run_opendrive_fuzz.sh SOURCE_DIR OPENDRIVE_DIR WORK_DIR [SECONDS]
set -euo pipefail
src=$1
third_party=${FLEET_TEST_DATA:-$2}
work=$3
seconds=${4:-20}
clang=${CLANGXX:-clang++-14}

if ! command -v "$clang" >/dev/null; then
  echo "run_opendrive_fuzz: $clang not found (install clang-14 libclang-rt-14-dev)" >&2
  exit 1
fi
mkdir -p "$work/corpus"
bin="$work/opendrive_fuzz"
sources=("$src/tests/fuzz/opendrive_fuzz.cpp" "$src/core/map/opendrive_parser.cpp" "$src/core/map/opendrive_eval.cpp"
         "$src/core/map/road_graph_builder.cpp" "$src/core/map/reference_samples.cpp")
# Rebuild only when a source changed.
rebuild=0
[ -x "$bin" ] || rebuild=1
for s in "${sources[@]}" "$src/core/map/opendrive.hpp" "$src/core/map/road_graph_builder.hpp" "$src/core/map/site.hpp"; do
  [ "$s" -nt "$bin" ] && rebuild=1
done
if [ $rebuild -eq 1 ]; then
  "$clang" -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -I"$src/core" "${sources[@]}" -lpugixml -o "$bin"
fi
# The corpus folder grows with what the fuzzer finds; seeds are copied in, never the reverse.
cp -f "$src"/maps/*.xodr "$work/corpus/"
if [ -d "$third_party" ]; then
  cp -f "$third_party"/*.xodr "$work/corpus/"
else
  echo "run_opendrive_fuzz: $third_party is absent: seeding with the shipped maps only" >&2
fi
cd "$work"
# The fuzzer's progress lines (a few hundred a run) are left out of the test's output, so that a
# failure elsewhere in the suite is not buried under them; crashes, timeouts and the final
# statistics are kept.
"$bin" -max_total_time="$seconds" -max_len=70000 -rss_limit_mb=2048 -timeout=10 \
  -print_final_stats=1 "$work/corpus" 2>&1 | { grep -v -E '^(#[0-9]+[[:space:]]+(NEW|REDUCE|pulse|RELOAD)|[[:space:]]+NEW_FUNC)' || true; }
exit "${PIPESTATUS[0]}"
