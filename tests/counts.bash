# counts.bash — the shell tests' tally (sourced): pass, fail with a message, and the closing
# "N passed, M failed" line whose status says whether anything failed.
passed=0
failed=0

pass() { passed=$((passed + 1)); }
fail() {
    failed=$((failed + 1))
    echo "FAIL: $*" >&2
}

summary() {
    echo "$passed passed, $failed failed"
    [[ $failed -eq 0 ]]
}
