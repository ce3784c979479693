# preview.sh — --preview: without a display (or without SDL2) it says so and renders the same image; under a
# virtual X server (Xvfb) the window shows the paper scene exactly as the file written, shows a lit image while a
# long render runs, and Esc, the window's close button or Ctrl-C stop the render with a partial image (exit 130);
# a finished render's window waits for Esc, Q or a signal.
# Arguments: GLINT SOURCE_DIR X11_PROBE|none SDL2(1|0). Exit 77 (skipped) when no X server can start.
source "$2/tests/cli/common.bash"
PROBE=${3:-none}
HAVE_SDL2=${4:-0}
# libdbus (which SDL uses) keeps a buffer it never frees: not a leak of glint's (ASan builds only).
export LSAN_OPTIONS="suppressions=$SRC/tests/lsan-sdl.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
PAPER=$SRC/scenes/paper.json
LONG=(--width 64 --height 48 --spp 1000000 "$DATA/tiny.json")

# The same image without a window: the reference for every file written here.
"$GLINT" -q "$PAPER" -o "$TMP/paper-plain.png" || fail "plain render of the paper scene"
"$GLINT" -q --width 64 --height 64 "$PAPER" -o "$TMP/small-plain.png" || fail "plain render of the small paper scene"

# No display: said once, the image written as without --preview, exit 0; --quiet says nothing.
SAID_NO_WINDOW="glint: --preview: no display (DISPLAY and WAYLAND_DISPLAY are unset); rendering without a window"
[[ $HAVE_SDL2 == 1 ]] || SAID_NO_WINDOW="glint: --preview: this glint was built without SDL2 (no window); rendering without a window"
env -u DISPLAY -u WAYLAND_DISPLAY timeout 120 "$GLINT" --preview --width 64 --height 64 "$PAPER" -o "$TMP/nodisplay.png" \
    >/dev/null 2>"$TMP/err"
rc=$?
check "no display: exit 0 (got $rc)" test $rc -eq 0
check "no display: says so" test "$(head -n 1 "$TMP/err")" == "$SAID_NO_WINDOW"
check "no display: the image of a render without --preview" cmp -s "$TMP/nodisplay.png" "$TMP/small-plain.png"
env -u DISPLAY -u WAYLAND_DISPLAY timeout 120 "$GLINT" -q --preview --width 64 --height 64 "$PAPER" -o "$TMP/quiet.png" 2>"$TMP/err"
check "no display, --quiet: nothing said" test ! -s "$TMP/err"

if [[ $HAVE_SDL2 != 1 ]]; then
    # A display changes nothing for a glint without SDL2.
    DISPLAY=:65000 timeout 120 "$GLINT" --preview --width 64 --height 64 "$PAPER" -o "$TMP/nosdl.png" >/dev/null 2>"$TMP/err"
    rc=$?
    check "without SDL2: exit 0 (got $rc)" test $rc -eq 0
    check "without SDL2: says so" test "$(head -n 1 "$TMP/err")" == "$SAID_NO_WINDOW"
    check "without SDL2: the image" cmp -s "$TMP/nosdl.png" "$TMP/small-plain.png"
    summary
    exit
fi

# A display that cannot be opened: SDL's reason, and the render goes on.
DISPLAY=:65000 timeout 120 "$GLINT" --preview --width 64 --height 64 "$PAPER" -o "$TMP/unreachable.png" >/dev/null 2>"$TMP/err"
rc=$?
check "unreachable display: exit 0 (got $rc)" test $rc -eq 0
check "unreachable display: says so" grep -q "^glint: --preview: cannot open a window on DISPLAY ':65000' (SDL: .*); rendering without a window$" "$TMP/err"
check "unreachable display: the image" cmp -s "$TMP/unreachable.png" "$TMP/small-plain.png"

# skip WHY: what ran so far must have passed; the rest cannot run here.
skip() {
    echo "SKIP: $* (the window tests did not run)"
    summary || exit 1
    exit 77
}
[[ $PROBE != none && -x $PROBE ]] || skip "no x11_probe (libx11-dev missing)"
command -v Xvfb >/dev/null || skip "Xvfb is not installed (Debian: xvfb)"
# Xvfb picks a free display number itself and writes it to fd 3 once it accepts clients.
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$TMP/display" 2>"$TMP/xvfb.log" &
XVFB=$!
trap 'kill $XVFB 2>/dev/null; wait $XVFB 2>/dev/null; rm -rf "$TMP"' EXIT
for _ in $(seq 100); do
    [[ -s $TMP/display ]] && break
    kill -0 $XVFB 2>/dev/null || break
    sleep 0.1
done
[[ -s $TMP/display ]] || skip "Xvfb did not start: $(tail -n 1 "$TMP/xvfb.log")"
export DISPLAY=:$(head -n 1 "$TMP/display")
unset WAYLAND_DISPLAY

# window TEXT: the id of glint's window once its title holds TEXT (empty after 60 s).
window() { "$PROBE" find "$1" 60; }
# title_spp WIN: waits (60 s) until the title says that every pixel has at least one sample.
title_spp() {
    local t
    for _ in $(seq 600); do
        t=$("$PROBE" title "$1" spp 0)
        [[ $t =~ -\ [1-9][0-9]*\ spp ]] && return 0
        sleep 0.1
    done
    echo "title: $t" >&2
    return 1
}

# The paper scene: the finished window shows exactly the file's pixels and waits; Esc ends the program, exit 0.
"$GLINT" "$PAPER" --preview -o "$TMP/paper.png" 2>"$TMP/err-paper" &
pid=$!
win=$(window "paper.json")
check "paper: a window titled after the scene" test -n "$win"
if [[ -n $win ]]; then
    check "paper: the title says done" "$PROBE" title "$win" "done, 1 spp" 60
    check "paper: the window shows exactly paper.png" "$PROBE" compare "$win" "$TMP/paper.png"
    check "paper: the window is lit" "$PROBE" lit "$win" 100000 10
    check "paper: the window waits after the image is written" kill -0 $pid
    "$PROBE" grab "$win" "$TMP/paper-window.ppm"
    "$PROBE" key "$win" Escape
fi
wait_for $pid
rc=$?
check "paper: Esc ends it, exit 0 (got $rc)" test $rc -eq 0
check "paper: paper.png as without --preview" cmp -s "$TMP/paper.png" "$TMP/paper-plain.png"
check "paper: says the window waits" grep -q 'preview window stays open' "$TMP/err-paper"

# A long render: its window shows samples while it runs; Esc stops it as Ctrl-C would.
"$GLINT" --preview -o "$TMP/esc.ppm" "${LONG[@]}" 2>"$TMP/err-esc" &
pid=$!
win=$(window "tiny.json")
if [[ -n $win ]] && title_spp "$win"; then
    check "Esc: the window shows the render while it runs" "$PROBE" lit "$win" 1000 10
    "$PROBE" key "$win" Escape
else
    fail "Esc: no window with samples"
fi
wait_for $pid
rc=$?
[[ $rc -eq 130 ]] || sed "s/^/  glint said: /" "$TMP/err-esc" >&2
check "Esc: exit 130 (got $rc)" test $rc -eq 130
check "Esc: complete-size P6" test "$(header "$TMP/esc.ppm" 13)" == " P 6 \n 6 4 4 8 \n 2 5 5 \n "
check "Esc: the image holds rendered samples" test "$(tail -c 9216 "$TMP/esc.ppm" | tr -d '\0' | wc -c)" -gt 0
check "Esc: says it was interrupted" grep -q 'interrupted; writing' "$TMP/err-esc"

# The window's close button (what a window manager sends): the same.
"$GLINT" -q --preview -o "$TMP/closed.ppm" "${LONG[@]}" 2>"$TMP/err-close" &
pid=$!
win=$(window "tiny.json")
if [[ -n $win ]] && title_spp "$win"; then "$PROBE" close "$win"; else fail "close: no window with samples"; fi
wait_for $pid
rc=$?
[[ $rc -eq 130 ]] || sed "s/^/  glint said: /" "$TMP/err-close" >&2
check "close: exit 130 (got $rc)" test $rc -eq 130
check "close: image written" test "$(size "$TMP/closed.ppm")" -eq $((13 + 64 * 48 * 3))
check "close: --quiet says nothing" test ! -s "$TMP/err-close"

# Ctrl-C in the terminal while the window shows the render: stops it, closes the window, exit 130.
"$GLINT" -q --preview -o "$TMP/sigint.ppm" "${LONG[@]}" 2>/dev/null &
pid=$!
win=$(window "tiny.json")
[[ -n $win ]] && title_spp "$win"
kill -INT $pid
wait_for $pid
rc=$?
check "SIGINT: exit 130 (got $rc)" test $rc -eq 130
check "SIGINT: image written" test "$(size "$TMP/sigint.ppm")" -eq $((13 + 64 * 48 * 3))

# Ctrl-C while a finished render's window waits: ends the program at once (the image is already written).
"$GLINT" -q --preview --width 64 --height 64 "$PAPER" -o "$TMP/waiting.png" &
pid=$!
win=$(window "paper.json")
[[ -n $win ]] && "$PROBE" title "$win" done 60 >/dev/null
kill -INT $pid
wait_for $pid
rc=$?
check "SIGINT while waiting: exit 130 (got $rc)" test $rc -eq 130
check "SIGINT while waiting: the image" cmp -s "$TMP/waiting.png" "$TMP/small-plain.png"

# Q closes a waiting window too.
"$GLINT" -q --preview --width 64 --height 64 "$PAPER" -o "$TMP/q.png" &
pid=$!
win=$(window "paper.json")
if [[ -n $win ]] && "$PROBE" title "$win" done 60 >/dev/null; then "$PROBE" key "$win" q; fi
wait_for $pid
rc=$?
check "Q: exit 0 (got $rc)" test $rc -eq 0

summary
