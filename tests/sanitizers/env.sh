# Sanitizer settings shared by tests/sanitizers/run.sh and tests/fuzz/run.sh (source it): stop at
# the first report, full stacks, leaks checked at exit with the committed suppressions (system
# libraries only, see lsan.supp).
sss_sanitizers_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export LSAN_OPTIONS="suppressions=$sss_sanitizers_dir/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# allocator_may_return_null: an allocation too large for ASan throws std::bad_alloc as it does in
# the Release build (the tools turn it into one error line) instead of aborting the test.
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:strict_string_checks=1:check_initialization_order=1"
unset sss_sanitizers_dir
