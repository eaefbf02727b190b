# Sourced by tests/sanitize.sh and tests/fuzz/run.sh (from the repository root): the clang
# build directory they share and the sanitizers' run-time options.
#   build-asan  everything with AddressSanitizer + UndefinedBehaviorSanitizer (SEMLOC_SANITIZE),
#               and the fuzz targets (SEMLOC_BUILD_FUZZERS; the library's parsing units with
#               libFuzzer's coverage)
# Optimized, with line tables for the reports' stack traces.
SEMLOC_ASAN_DIR=${SEMLOC_ASAN_DIR:-build-asan}
semloc_clang_flags=(-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo
                    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG"
                    -DSEMLOC_SANITIZE=ON -DSEMLOC_BUILD_FUZZERS=ON -DSEMLOC_BUILD_BENCHMARKS=OFF)

# semloc_configure: configures $SEMLOC_ASAN_DIR once (the benchmarks are not part of the
# suite), and again if an earlier configuration left the fuzz targets out.
semloc_configure()
{
    grep -qx 'SEMLOC_BUILD_FUZZERS:BOOL=ON' "$SEMLOC_ASAN_DIR/CMakeCache.txt" 2>/dev/null ||
        cmake -S . -B "$SEMLOC_ASAN_DIR" "${semloc_clang_flags[@]}"
}

# Any finding aborts with a stack trace; leaks inside third-party libraries that semloc
# cannot change are suppressed, each explained, in tests/lsan.supp.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/lsan.supp:print_suppressions=0}
