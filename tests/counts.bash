# counts.bash — what every shell test shares (sourced): the tally (pass, fail with a message, check, and the
# closing "N passed, M failed" line whose status says whether anything failed), wait_for and wait_caught.
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

# wait_caught PID SIG [TENTHS]: waits (default 30 s) until the process catches SIG (its handler is installed, as
# /proc/PID/status's SigCgt mask says), so that a signal sent next reaches the program, not the default action
# that would kill it before it has begun; a loaded machine can take longer than any fixed sleep to get there.
wait_caught() {
    local pid=$1 bit=$(($(kill -l "$2") - 1)) mask
    for _ in $(seq "${3:-300}"); do
        mask=$(awk '/^SigCgt:/ { print $2 }' "/proc/$pid/status" 2>/dev/null)
        [[ -n $mask ]] && (((16#$mask >> bit) & 1)) && return 0
        kill -0 "$pid" 2>/dev/null || return 1
        sleep 0.1
    done
    return 1
}
