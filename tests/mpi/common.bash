# common.bash — helpers shared by glint-mpi's tests (sourced, not a test itself): the programs, mpirun with
# the flags a test machine needs, a temporary directory, and the tally of tests/counts.bash.
GLINT=$1
GLINT_MPI=$2
SRC=$3
if [[ ! -x $GLINT || ! -x $GLINT_MPI || ! -d $SRC ]]; then
    echo "usage: $0 GLINT GLINT_MPI SOURCE_DIR" >&2
    exit 2
fi
DATA=$SRC/tests/data
TMP=$(mktemp -d "${TMPDIR:-/tmp}/glint-mpi-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
# shellcheck source=../counts.bash
source "$SRC/tests/counts.bash"

# More ranks than cores (CI machines have two); as root (containers), Open MPI must be told it is wanted.
MPIRUN=(mpirun --oversubscribe)
[[ $(id -u) == 0 ]] && MPIRUN+=(--allow-run-as-root)
# Under the sanitizers (GLINT_SANITIZE=1, set by CTest), leaks inside the MPI libraries are theirs, not
# glint's (tests/mpi/lsan.supp); the full, slow unwinding of every allocation lets the suppressions see the
# library frames, which the fast unwinder loses in libraries built without frame pointers.
if [[ -n ${GLINT_SANITIZE:-} ]]; then
    export LSAN_OPTIONS="suppressions=$SRC/tests/mpi/lsan.supp:print_suppressions=0:fast_unwind_on_malloc=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fi

