# common.bash — helpers shared by the CLI tests (sourced, not a test itself): run glint, compare exit
# status and messages, inspect image files, count results and print "N passed, M failed".
GLINT=$1
SRC=$2
if [[ ! -x $GLINT || ! -d $SRC ]]; then
    echo "usage: $0 GLINT_BINARY SOURCE_DIR" >&2
    exit 2
fi
DATA=$SRC/tests/data
TMP=$(mktemp -d "${TMPDIR:-/tmp}/glint-cli-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
# shellcheck source=../counts.bash
source "$SRC/tests/counts.bash"

# run ARGS...: runs glint; exit status in $rc, standard output in $TMP/out, standard error in $TMP/err.
run() {
    "$GLINT" "$@" >"$TMP/out" 2>"$TMP/err" </dev/null
    rc=$?
}

# expect STATUS STDERR ARGS...: glint ARGS must exit with STATUS and print exactly STDERR.
expect() {
    local status=$1 message=$2
    shift 2
    run "$@"
    local got
    got=$(cat "$TMP/err")
    if [[ $rc -eq $status && $got == "$message" ]]; then
        pass
    else
        fail "glint $*: exit $rc (expected $status), stderr:
$got
expected:
$message"
    fi
}

# size FILE: its size in bytes.
size() { stat -c %s "$1"; }

# header FILE N: its first N bytes, shown by od as characters.
header() { head -c "$2" "$1" | od -An -c | tr -s ' \n' ' '; }

# be32 FILE OFFSET: the big-endian 32-bit integer at OFFSET.
be32() { od -An -tu1 -j "$2" -N 4 "$1" | awk '{ print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4 }'; }

# differ A B: the two files are not identical.
differ() { ! cmp -s "$1" "$2"; }

# no_temp_files DIR: nothing glint's temporary files look like (".NAME.tmp-XXXXXX") is left in DIR.
no_temp_files() { ! ls -A "$1" | grep -q '\.tmp-'; }
