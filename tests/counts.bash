# counts.bash — what every shell test shares (sourced): the tally (pass, fail with a message, check, and the
# closing "N passed, M failed" line whose status says whether anything failed) and wait_for.
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

# check DESCRIPTION COMMAND...: passes when the command succeeds.
check() {
    local what=$1
    shift
    if "$@"; then pass; else fail "$what"; fi
}

# wait_for PID [TENTHS]: its exit status, or 255 (and a kill) if it still runs after TENTHS/10 s (default 60 s).
wait_for() {
    local pid=$1
    for _ in $(seq "${2:-600}"); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.1
    done
    if kill -0 "$pid" 2>/dev/null; then
        kill -KILL "$pid"
        wait "$pid" 2>/dev/null
        return 255
    fi
    wait "$pid"
}
