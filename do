#!/usr/bin/env bash
# cobra's one entry point. Usage: ./do <command> [options]
#   setup            install the Debian packages cobra needs (idempotent; quick when present)
#   build [P [T...]] configure and build preset P (release (default), asan, tsan), or its targets T
#   test             build and run every test (unit tests, examples)
#   test --asan      the same under AddressSanitizer + UndefinedBehaviorSanitizer
#   test --asan-ci   the CI's ASan/UBSan slice: parsers, channels, real-time code, components, puncturing
#   test --tsan      the tests that run threads under ThreadSanitizer (label concurrency)
#   test --wallclock only the wall-clock tests (label wallclock: each task on the real-time
#                    executor, and wallclock_split: the puncturing task split over two hosts;
#                    minutes of wall time; `./do test` runs them too, one wall-clock test at
#                    a time beside the other tests)
#   demo [basics|puma260|suturing]  build and run the puncturing procedure in simulation (basics:
#                    the small demos; puma260: the retrofitted Puma 260 task, thesis ch. 6;
#                    suturing: the two-armed suturing task, thesis ch. 5)
#   bench            build and run the benchmarks (Google Benchmark; median and max; installs
#                    rt-tests and stress-ng for the executor's bench beside cyclictest)
#   fuzz [seconds]   build the libFuzzer targets (clang) and run each for [60] seconds, two at a time
#   fuzz-seeds       check that every fuzzer's seed files (the repo's real inputs) exist
#   screenshots      build cobra and the studio page, render docs/screenshots/*.png (tools/screenshots.sh)
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(cmake ninja-build ccache mold g++ libgtest-dev libbenchmark-dev liborocos-kdl-dev libeigen3-dev liblua5.4-dev libcli11-dev libgmock-dev graphviz libedit-dev libboost-dev libompl-dev libfcl-dev libassimp-dev libmujoco-dev chromium libfastrtps-dev fastddsgen nlohmann-json3-dev libopenigtlink-dev openssl libssl-dev)
FUZZ_PACKAGES=(clang libclang-rt-14-dev)
# executor_bench's peer (cyclictest) and its load (stress-ng --cpu).
BENCH_PACKAGES=(rt-tests stress-ng)
# Leaks of libraries cobra cannot free, each explained in the file; ASan's leak check stays on.
LSAN="suppressions=$PWD/test_support/lsan.supp:print_suppressions=0"
# Reports inside Debian's uninstrumented Fast DDS, each explained in the file.
TSAN_SUPP="suppressions=$PWD/test_support/tsan.supp:print_suppressions=0"
# Every fuzzer is a fuzz/<name>_fuzz.cpp (fuzz/CMakeLists.txt builds each, and the target fuzzers all).
FUZZERS=($(cd fuzz && ls -- *_fuzz.cpp | sed 's/\.cpp$//'))

# The repo's real files a fuzzer starts from (copied into one folder, as libFuzzer takes folders).
fuzz_seeds() {
  case "$1" in
    chart_loader_fuzz) echo script/test/charts/* ;;
    phantom_scenario_fuzz) echo apps/puncturing/scenarios/*/phantom.txt ;;
    planning_scene_fuzz) echo apps/*/deployment/*.scene planning/test/scenes/*.scene planning/test/data/*.scene ;;
    puncturing_plan_fuzz) echo apps/puncturing/scenarios/*/*.txt apps/puncturing/state_table.txt ;;
    studio_json_fuzz) echo studio/test/fuzz_seeds/*.json ;;
    studio_http_fuzz) echo studio/test/fuzz_seeds/*.http studio/test/fuzz_seeds/input.json ;;
    igtl_message_fuzz) echo bridges/test/igtl_seeds/*.igtl ;;
  esac
}

# Fails, naming the fuzzer and the pattern, when a seed pattern above matches no file (a moved
# folder would otherwise end the fuzz slice with cp's bare "cannot stat"). `./do fuzz-seeds` runs
# only this check; `./do test` runs it too (test do_fuzz_seeds_exist).
check_fuzz_seeds() {
  local f seed bad=0
  for f in "${FUZZERS[@]}"; do
    for seed in $(fuzz_seeds "$f"); do
      if [ ! -f "$seed" ]; then
        echo "do fuzz: the seed pattern '$seed' of $f matches no file; fix fuzz_seeds in ./do" >&2
        bad=1
      fi
    done
  done
  return $bad
}

# Runs fuzzer $1 for $2 seconds from the repo's seeds and its corpus; its output to build/fuzz/$1.log.
run_fuzzer() {
  local f=$1 seconds=$2 seed
  mkdir -p "build/fuzz/corpus/$f"
  rm -rf "build/fuzz/seeds/$f"; mkdir -p "build/fuzz/seeds/$f"  # read-only starting inputs
  for seed in $(fuzz_seeds "$f"); do cp "$seed" "build/fuzz/seeds/$f/${seed//\//_}"; done
  "./build/fuzz/fuzz/$f" -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="build/fuzz/$f-" \
    "build/fuzz/corpus/$f" "build/fuzz/seeds/$f" >"build/fuzz/$f.log" 2>&1
}

# The lab's test certificates (tools/make_test_pki.sh: a test CA, host identities, a TLS server
# certificate, signed DDS Security documents) in build/pki, made before the tests and the demos.
# Idempotent and quick when they are current.
TEST_PKI=build/pki
make_test_pki() { setup; tools/make_test_pki.sh "$TEST_PKI"; }

say() { printf '\033[1m[do]\033[0m %s\n' "$*"; }

setup() {
  local missing=()
  for p in "${PACKAGES[@]}" "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  say "installing Debian packages: ${missing[*]}"
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "do: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
    sudo=(sudo)
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# Shows a running build: on a terminal one updating line (Ninja's step n/N, the elapsed time and
# what it is doing), otherwise Ninja's own lines with the elapsed seconds. Reads the build's
# output on stdin; the whole output goes to the log named by $1.
show_progress() {
  local log=$1 start=$SECONDS chunk partial="" line step="" what="configuring" width
  if [ ! -t 1 ]; then tee "$log"; return; fi
  width=$(tput cols 2>/dev/null || echo 80)
  while :; do
    if IFS= read -r -t 1 chunk; then
      line=$partial$chunk partial=""
      printf '%s\n' "$line" >>"$log"
      if [[ $line =~ ^\[([0-9]+)/([0-9]+)\]\ (.*)$ ]]; then
        step="step ${BASH_REMATCH[1]}/${BASH_REMATCH[2]}, " what=${BASH_REMATCH[3]}
      fi
    elif [ $? -gt 128 ]; then  # a second without a whole line: keep what came, refresh the clock
      partial+=$chunk
    else  # the end of the output
      [ -z "$partial$chunk" ] || printf '%s\n' "$partial$chunk" >>"$log"
      break
    fi
    line=$(printf '[do] building: %s%dm%02ds  %s' "$step" $(((SECONDS - start) / 60)) $(((SECONDS - start) % 60)) "$what")
    printf '\r\033[K%s' "${line:0:width-1}"
  done
  printf '\r\033[K'
}

# Configures (once) and builds preset $1 with the cmake --build options that follow, showing its
# progress; on failure prints the tail of the log and where the whole log is.
build() {
  local preset="${1:-release}" log status="[%f/%t] "
  [ -t 1 ] || status="[%f/%t, %es] "  # plain lines say the elapsed seconds themselves
  if [ "$preset" = fuzz ]; then setup "${FUZZ_PACKAGES[@]}"; else setup; fi
  mkdir -p build
  sh studio/web/tools/npm_ci_if_needed.sh  # quick and offline when node_modules is current
  log="build/$preset.log"
  : >"$log"
  if ! { { [ -f "build/$preset/build.ninja" ] || cmake --preset "$preset"; } &&
         NINJA_STATUS=$status cmake --build --preset "$preset" "${@:2}"; } 2>&1 | show_progress "$log"; then
    tail -n 30 "$log" >&2
    echo "do: the $preset build failed; the whole log is $PWD/$log" >&2
    exit 1
  fi
}

run_tests() {
  case "${1:-}" in
    "")
      build release
      ctest --test-dir build/release --output-on-failure --no-tests=error -j2 --timeout 300 ;;
    --wallclock)
      build release
      ctest --test-dir build/release --output-on-failure --no-tests=error --timeout 300 -L '^wallclock' ;;
    --asan)
      build asan
      # Every test, the whole tasks on the wall clock too (one at a time, as in `./do test`).
      ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 LSAN_OPTIONS=$LSAN \
        ctest --test-dir build/asan --output-on-failure --no-tests=error -j2 --timeout 900 ;;
    --asan-ci)
      # Only the slice's test executables and what they link (COBRA_TEST_LABELS in the preset).
      build asan-ci --target selected_tests
      labels=$(sed -n 's/^COBRA_TEST_LABELS:STRING=//p' build/asan-ci/CMakeCache.txt | tr ';' '|')
      ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 LSAN_OPTIONS=$LSAN \
        ctest --test-dir build/asan-ci --output-on-failure --no-tests=error -j2 --timeout 600 -L "^($labels)\$" ;;
    --tsan)
      # Only the tests that run threads (label "concurrency": core's activities and ports, deploy,
      # the bridges, the DDS transport and link, the studio server; the tsan preset's
      # COBRA_TEST_LABELS, built by selected_tests); the rest is single-threaded and covered by the
      # other builds. Races inside Debian's uninstrumented Fast DDS are suppressed by its frames
      # only (test_support/tsan.supp says which and why).
      build tsan --target selected_tests
      TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:$TSAN_SUPP \
        ctest --test-dir build/tsan --output-on-failure --no-tests=error -L concurrency --timeout 600 ;;
    *) echo "do test: unknown option '$1' (expected --asan, --asan-ci, --tsan or --wallclock)" >&2; exit 2 ;;
  esac
}

case "${1:-help}" in
  setup) setup ;;
  build)
    if [ $# -gt 2 ]; then build "$2" --target "${@:3}"; else build "${2:-release}"; fi ;;
  test) shift; make_test_pki; run_tests "${1:-}" ;;
  demo)
    make_test_pki
    if [ "${2:-}" = basics ]; then
      say "building the basic demos (first time: installs packages and compiles, a few minutes)"
      build release --target cobra example_04_trajectory example_05_variable_admittance
      say "a signal deployment with a one-chart task, run by cobra run (apps/demo: files only)"
      ./build/release/tools/cobra/cobra run apps/demo --report "$PWD/build/demo-basic-report"
      say "the thesis' Fig. 3.5: a synchronised multi-axis trajectory (examples/04_trajectory.cpp)"
      ./build/release/examples/example_04_trajectory /tmp/cobra-fig-3-5.svg
      say "the tank-based variable admittance library on a point against a bump (examples/05_variable_admittance.cpp)"
      ./build/release/examples/example_05_variable_admittance /tmp/cobra-variable-admittance.svg
      say "the thesis' door task (Figs. 2.5-2.6): three supervisors on a simulated door (apps/door)"
      ./build/release/tools/cobra/cobra run apps/door
    elif [ "${2:-}" = puma260 ]; then
      say "building the Puma 260 demo (first time: installs packages and compiles, 15-20 minutes on 2 cores)"
      build release --target cobra
      say "the thesis' retrofitted Puma 260 (ch. 6): a linear path across an unexpected surface (cobra run apps/puma260)"
      ./build/release/tools/cobra/cobra run apps/puma260 --report "$PWD/build/demo-puma260-report"
      say "Fig. 6.7 (nominal and actual tool path, phases A-H) is the report's first figure"
    elif [ "${2:-}" = suturing ]; then
      say "building the suturing demo (first time: installs packages and compiles, 15-20 minutes on 2 cores)"
      build release --target cobra
      say "the thesis' suturing task (ch. 5) in simulation: a 40 mm cut closed with 4 stitches (cobra run apps/suturing)"
      ./build/release/tools/cobra/cobra run apps/suturing --report "$PWD/build/demo-suturing-report"
    elif [ -n "${2:-}" ]; then
      echo "do demo: unknown demo '$2' (expected basics, puma260 or suturing)" >&2; exit 2
    else
      say "building the puncturing demo (first time: installs packages and compiles, 15-20 minutes on 2 cores)"
      build release --target cobra
      say "the thesis' puncturing task (ch. 4) in simulation: two robots, two needles (cobra run apps/puncturing)"
      ./build/release/tools/cobra/cobra run apps/puncturing --report "$PWD/build/demo-report"
    fi ;;
  bench)
    setup "${BENCH_PACKAGES[@]}"
    build release
    # The applications' packages and cobra's charts, where the build puts them (bench/CMakeLists.txt).
    . build/release/bench/bench_environment.sh
    for b in build/release/bench/*_bench; do
      say "$b"
      "$b" --benchmark_counters_tabular=true
    done ;;
  screenshots) build release --target cobra studio_web && tools/screenshots.sh ;;
  fuzz-seeds) check_fuzz_seeds ;;
  fuzz)
    seconds="${2:-60}"
    check_fuzz_seeds
    build fuzz --target fuzzers
    # Two fuzzers at a time (each is single-threaded; the machine has two cores).
    for ((i = 0; i < ${#FUZZERS[@]}; i += 2)); do
      pair=("${FUZZERS[@]:i:2}") pids=()
      say "${pair[*]} for ${seconds} s"
      for f in "${pair[@]}"; do run_fuzzer "$f" "$seconds" & pids+=($!); done
      for j in "${!pair[@]}"; do
        f=${pair[j]}
        if ! wait "${pids[j]}"; then
          tail -n 40 "build/fuzz/$f.log"
          echo "do fuzz: $f found a failure; the input is saved under build/fuzz/ as $f-crash-* (see above)" >&2
          exit 1
        fi
        grep -E '^(Done|stat::number_of_executed_units)' "build/fuzz/$f.log" | sed "s/^/$f: /" || true
      done
    done ;;
  help|-h|--help) sed -n '2,/^set -euo/{/^#/p}' "$0" | sed 's/^# \{0,1\}//' ;;
  *) echo "do: unknown command '$1'" >&2; sed -n '2,/^set -euo/{/^#/p}' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2 ;;
esac
