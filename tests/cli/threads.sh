# threads.sh — every scene of scenes/ renders the same bytes on one thread and on two (at a small size and
# sample count, so that the whole set takes seconds): the promise each new feature must keep.
source "$2/tests/cli/common.bash"

for scene in "$SRC"/scenes/*.json; do
    name=$(basename "$scene" .json)
    for threads in 1 2; do
        run -q --width 40 --height 24 --spp 3 --threads $threads "$scene" -o "$TMP/$name-$threads.pfm"
        check "$name on $threads thread(s): exit 0 (got $rc: $(head -c 300 "$TMP/err"))" test "$rc" -eq 0
    done
    check "$name: the same bytes on 1 and 2 threads" cmp -s "$TMP/$name-1.pfm" "$TMP/$name-2.pfm"
done
summary
