#!/usr/bin/env bash
# check.sh — installs the build tree into a temporary prefix and uses it as a client would: pkg-config,
# render.c built with gcc and clang against libglint.so and libglint.a, the exported symbols, the man page.
# usage: check.sh CMAKE BUILD_DIR SOURCE_DIR C_COMPILER_ID SANITIZE(0|1)
# "COND && pass || fail" is safe here: pass cannot fail.
# shellcheck disable=SC2015
set -euo pipefail
if [[ $# -ne 5 ]]; then
    echo "usage: $0 CMAKE BUILD_DIR SOURCE_DIR C_COMPILER_ID SANITIZE" >&2
    exit 2
fi
CMAKE=$1
BUILD=$2
SRC=$3
BUILT_WITH=$4
SANITIZE=$5
TMP=$(mktemp -d "${TMPDIR:-/tmp}/glint-install-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
PREFIX=$TMP/prefix
# shellcheck source=../counts.bash
source "$SRC/tests/counts.bash"

"$CMAKE" --install "$BUILD" --prefix "$PREFIX" >"$TMP/install.log"

# The library directory is GNUInstallDirs' choice (lib or lib/<multiarch>): find it from the .pc file.
shopt -s nullglob
pcs=("$PREFIX"/lib*/pkgconfig/glint.pc "$PREFIX"/lib/*/pkgconfig/glint.pc)
shopt -u nullglob
if [[ ${#pcs[@]} -ne 1 ]]; then
    echo "FAIL: expected one installed glint.pc, found ${#pcs[@]}" >&2
    cat "$TMP/install.log" >&2
    exit 1
fi
PKG_CONFIG_PATH=$(dirname "${pcs[0]}")
export PKG_CONFIG_PATH
LIBDIR=$(pkg-config --variable=libdir glint)
VERSION=$(pkg-config --modversion glint)
MAJOR=${VERSION%%.*}
# The ABI's name: the major version, or major.minor before 1.0 (CMakeLists.txt, GLINT_SOVERSION).
if [[ $MAJOR == 0 ]]; then MINOR=${VERSION#*.}; MAJOR=0.${MINOR%%.*}; fi

# --- The installed files, and the shared library's version chain
for f in "$PREFIX/bin/glint" "$PREFIX/include/glint.h" "$PREFIX/include/glint/status.h" "$PREFIX/share/man/man1/glint.1" "$LIBDIR/libglint.a" \
    "$LIBDIR/libglint.so.$VERSION"; do
    if [[ -f $f ]]; then pass; else fail "not installed: ${f#"$PREFIX/"}"; fi
done
[[ $(readlink "$LIBDIR/libglint.so") == "libglint.so.$MAJOR" ]] && pass || fail "libglint.so does not link to libglint.so.$MAJOR"
[[ $(readlink "$LIBDIR/libglint.so.$MAJOR") == "libglint.so.$VERSION" ]] && pass ||
    fail "libglint.so.$MAJOR does not link to libglint.so.$VERSION"
readelf -d "$LIBDIR/libglint.so.$VERSION" >"$TMP/dynamic"
if grep -q "SONAME.*\[libglint.so.$MAJOR\]" "$TMP/dynamic"; then pass; else
    fail "SONAME is not libglint.so.$MAJOR"
fi
[[ $(pkg-config --variable=prefix glint) == "$PREFIX" ]] && pass || fail "glint.pc's prefix is not $PREFIX"
[[ $("$PREFIX/bin/glint" --version) == "glint $VERSION" ]] && pass || fail "installed glint --version is not $VERSION"

# --- libglint.so exports exactly the functions glint.h declares GLINT_API: nothing internal leaks
nm -D --defined-only "$LIBDIR/libglint.so" | awk '{print $NF}' | sort >"$TMP/exported"
grep '^GLINT_API' "$PREFIX/include/glint.h" | grep -o 'glint_[a-z0-9_]*(' | tr -d '(' | sort >"$TMP/declared"
if [[ $(wc -l <"$TMP/declared") -lt 10 ]]; then
    fail "found only $(wc -l <"$TMP/declared") GLINT_API declarations in glint.h"
elif diff "$TMP/declared" "$TMP/exported" >"$TMP/symbols.diff"; then
    pass
else
    fail "libglint.so's exports differ from glint.h's GLINT_API functions (< declared only, > exported only):"
    cat "$TMP/symbols.diff" >&2
fi

# --- The man page reads without a warning and documents every option of --help
man_page=$PREFIX/share/man/man1/glint.1
if groff -man -Tutf8 -ww -z "$man_page" 2>"$TMP/groff.err" && [[ ! -s $TMP/groff.err ]]; then pass; else
    fail "groff warns about glint.1:"
    cat "$TMP/groff.err" >&2
fi
if command -v man >/dev/null; then
    if MANWIDTH=80 man -l "$man_page" >"$TMP/man.txt" 2>"$TMP/man.err" && [[ ! -s $TMP/man.err ]] &&
        grep -q '^NAME' "$TMP/man.txt"; then pass; else
        fail "man -l does not read glint.1 cleanly:"
        cat "$TMP/man.err" >&2
    fi
else
    echo "note: man is not installed; glint.1 checked with groff alone"
fi
groff -man -Tascii -P-cbou "$man_page" 2>/dev/null >"$TMP/man.ascii"
"$PREFIX/bin/glint" --help >"$TMP/help"
while read -r opt; do
    grep -qE -- "(^|[^a-zA-Z-])$opt([^a-zA-Z-]|$)" "$TMP/man.ascii" && pass || fail "glint.1 does not document $opt"
done < <(grep -oE -- '(^|[ ,])--?[a-zA-Z][a-z-]*' "$TMP/help" | grep -oE -- '--?[a-zA-Z][a-z-]*' | sort -u)
for status in 0 1 2 130 143; do
    grep -qE "^ +$status +[A-Z]" "$TMP/man.ascii" && pass || fail "glint.1's EXIT STATUS does not list $status"
done

# --- render.c built against the installed library, with each compiler, linked shared and linked static
CFLAGS=(-std=c17 -O2 -Wall -Wextra -Wpedantic -Werror)
# pkg-config --static --libs, without -lglint itself: the archive is named by its path instead, so that
# the linker cannot take libglint.so from the same directory.
static_libs=()
read -ra words <<<"$(pkg-config --static --libs glint)"
for word in "${words[@]}"; do
    [[ $word == -lglint ]] || static_libs+=("$word")
done
read -ra pc_cflags <<<"$(pkg-config --cflags glint)"
read -ra pc_cflags_libs <<<"$(pkg-config --cflags --libs glint)"

# build_and_run NAME COMPILER ARGS...: compiles render.c, runs it, keeps its image as $TMP/NAME.ppm.
build_and_run() {
    local name=$1 cc=$2
    shift 2
    if ! "$cc" "${CFLAGS[@]}" "$@" -o "$TMP/$name" 2>"$TMP/$name.err"; then
        fail "$name: cannot build:"
        cat "$TMP/$name.err" >&2
        return
    fi
    if "$TMP/$name" "$TMP/$name.ppm" >"$TMP/$name.out" 2>&1; then pass; else
        fail "$name: the program failed:"
        cat "$TMP/$name.out" >&2
        return
    fi
    # A shared build must load the installed libglint.so; a static one must not need it at all.
    # (ldd's output is kept first: grep -q stops reading at a match, and pipefail would count ldd's SIGPIPE.)
    ldd "$TMP/$name" >"$TMP/$name.ldd"
    if [[ $name == *shared* ]]; then
        grep -q "libglint.so.$MAJOR => $LIBDIR/" "$TMP/$name.ldd" && pass || fail "$name does not load $LIBDIR/libglint.so"
    else
        ! grep -q libglint "$TMP/$name.ldd" && pass || fail "$name needs libglint.so, expected the archive linked in"
    fi
    echo "$name: $(tail -n 1 "$TMP/$name.out")"
}

for cc in gcc clang; do
    if ! command -v "$cc" >/dev/null; then
        if [[ $cc == clang ]]; then
            echo "SKIP: clang is not installed; the installed library is tested with gcc alone"
            continue
        fi
        fail "gcc is not installed"
        continue
    fi
    san=()
    if [[ $SANITIZE == 1 ]]; then
        # The installed library is instrumented here, and needs the sanitizer runtime of the compiler that
        # built it: another compiler's runtime is a different library.
        sanitizer_cc=none
        [[ $BUILT_WITH == GNU ]] && sanitizer_cc=gcc
        [[ $BUILT_WITH == Clang ]] && sanitizer_cc=clang
        if [[ $cc != "$sanitizer_cc" ]]; then
            echo "SKIP: $cc: this GLINT_SANITIZE build's library is instrumented by $BUILT_WITH, whose runtime $cc lacks"
            continue
        fi
        # shellcheck disable=SC2054 # one option, not two array elements
        san=(-fsanitize=address,undefined)
    fi
    build_and_run "$cc-shared" "$cc" "${san[@]}" "$SRC/tests/install/render.c" "${pc_cflags_libs[@]}" \
        -Wl,-rpath,"$LIBDIR"
    build_and_run "$cc-static" "$cc" "${san[@]}" "${pc_cflags[@]}" "$SRC/tests/install/render.c" \
        "$LIBDIR/libglint.a" "${static_libs[@]}"
    if [[ $cc == gcc ]]; then
        # gcc without LTO reads the archive's machine code, not its LTO objects.
        build_and_run "$cc-static-no-lto" "$cc" -fno-lto "${san[@]}" "${pc_cflags[@]}" \
            "$SRC/tests/install/render.c" "$LIBDIR/libglint.a" "${static_libs[@]}"
    fi
done

# Renders are deterministic: every build of the client must have written the same bytes.
images=("$TMP"/*.ppm)
if [[ ! -f ${images[0]} ]]; then
    fail "no client wrote an image"
else
    for img in "${images[@]}"; do
        cmp -s "${images[0]}" "$img" && pass || fail "$(basename "$img") differs from $(basename "${images[0]}")"
    done
fi

summary
