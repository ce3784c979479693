#!/usr/bin/env bash
# bench/plot.sh — draws the plots of one benchmark run as SVG with gnuplot (Debian: gnuplot-nox), from the
# data files bench/run.sh keeps beside its table, into the same directory.
#
# usage: bash bench/plot.sh DIR      (DIR: bench/results/DATE-COMMIT[-quick], holding the .dat files)
#
# Draws what the data files present allow (a missing file, or one without rows, is skipped):
#   speedup.dat   -> speedup.svg        speedup against threads, glint and the yardsticks (Howard's plot);
#                                       points above the number of CPUs marked as oversubscribed
#   versus.dat    -> mrays.svg          glint against Embree: Mrays/s of the render loop, bars
#   meshyard.dat  -> process.svg        whole process (OBJ read, build, render) in seconds, bars
#   meshscale.dat -> scale-nsray.svg    ns per ray against triangles (log x), one thread
#                    scale-build.svg    BVH build seconds against triangles (log-log)
#                    scale-memory.svg   peak memory per triangle against triangles (log x)
#   cycles.dat    -> cycles-SCENE.svg   RMSE against render time (log-log), glint and Cycles at each thread count
# The data files' columns are named on their first line ("# ..."); nan marks a figure not measured.
set -euo pipefail
export LC_ALL=C

[ $# -eq 1 ] || { echo "usage: bash bench/plot.sh DIR" >&2; exit 2; }
case "$1" in -h | --help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
DIR=$1
[ -d "$DIR" ] || { echo "bench/plot.sh: $DIR: no such directory" >&2; exit 2; }
command -v gnuplot >/dev/null || { echo "bench/plot.sh: gnuplot is not installed (Debian: apt-get install gnuplot-nox)" >&2; exit 1; }
RUN=$(basename "$(cd "$DIR" && pwd)")
TMP=$(mktemp -d "${TMPDIR:-/tmp}/glint-plot.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

# rows FILE: true when FILE exists and has a data row
rows() { [ -f "$1" ] && grep -qv '^#' "$1"; }

# The common head of every plot: SVG, white background, the run's name in the title, missing values.
head_of() { # OUT TITLE KEY: KEY places the legend (gnuplot's "set key" words)
    cat <<GP
set terminal svg size 760,480 dynamic noenhanced font "sans,12" background rgb "white"
set output "$1"
set title "$2\n$RUN"
set datafile missing "nan"
set grid lc rgb "#dddddd"
set key $3 box opaque
GP
}

# label BENCH RENDERER: the legend's name of a series
label() {
    case $2 in
    glint) echo "glint, $1" ;;
    embree-probe) echo "Embree probe, $1" ;;
    embree-mesh) echo "Embree mesh yardstick, $1" ;;
    *) echo "$2, $1" ;;
    esac
}

# Written to TMP first and moved into place: a failed gnuplot leaves no partial SVG behind.
draw() { # NAME.svg: runs $TMP/plot.gp
    gnuplot "$TMP/plot.gp" || { echo "bench/plot.sh: gnuplot failed on $1" >&2; exit 1; }
    mv "$TMP/out.svg" "$DIR/$1"
    echo "wrote $DIR/$1" >&2
}

# --- speedup against threads -------------------------------------------------------------------------
if rows "$DIR/speedup.dat"; then
    maxt=$(awk '!/^#/ && $3 > m { m = $3 } END { print m + 0 }' "$DIR/speedup.dat")
    {
        head_of "$TMP/out.svg" "Speedup against threads" "top left"
        echo "set xlabel 'threads'; set ylabel 'speedup: Mrays/s on N threads / on 1 (Howard: wall times)'"
        echo "set xrange [0.8:$maxt + 0.2]; set yrange [0:$maxt + 0.5]; set xtics 1"
        printf 'plot x title "ideal" lc rgb "#999999" dt 3'
        i=0
        while read -r bench renderer; do
            i=$((i + 1))
            awk -v b="$bench" -v r="$renderer" '!/^#/ && $1 == b && $2 == r { print $3, $6 }' "$DIR/speedup.dat" >"$TMP/s$i"
            # glint solid, yardsticks dashed
            dt=$([ "$renderer" = glint ] && echo 1 || echo 2)
            printf ', "%s" using 1:2 with linespoints lw 2 dt %s pt 7 title "%s"' "$TMP/s$i" "$dt" "$(label "$bench" "$renderer")"
        done < <(awk '!/^#/ && !seen[$1 " " $2]++ { print $1, $2 }' "$DIR/speedup.dat")
        awk '!/^#/ && $4 == 1 { print $3, $6 }' "$DIR/speedup.dat" >"$TMP/over"
        if [ -s "$TMP/over" ]; then
            printf ', "%s" using 1:2 with points pt 6 ps 2.5 lc rgb "black" title "oversubscribed (threads > CPUs)"' "$TMP/over"
        fi
        echo
    } >"$TMP/plot.gp"
    draw speedup.svg
fi

# --- glint against Embree: Mrays/s bars --------------------------------------------------------------
if rows "$DIR/versus.dat"; then
    {
        head_of "$TMP/out.svg" "glint against Embree: Mrays/s of the render loop" "top right"
        echo "set style data histograms; set style histogram clustered gap 1; set style fill solid 0.8 border -1"
        echo "set ylabel 'Mrays/s'; set yrange [0:*]; set xtics rotate by -30"
        echo "plot '$DIR/versus.dat' using 2:xtic(1) title 'glint' lc rgb '#d95f02', '' using 3 title 'Embree' lc rgb '#1b9e77'"
    } >"$TMP/plot.gp"
    draw mrays.svg
fi

# --- whole process: bars -----------------------------------------------------------------------------
if rows "$DIR/meshyard.dat"; then
    awk '!/^#/ { printf "%s/%st %s %s\n", $1, $3, $11, $10 }' "$DIR/meshyard.dat" >"$TMP/process"
    {
        head_of "$TMP/out.svg" "Whole process: OBJ read, build and render (lower is faster)" "top left"
        echo "set style data histograms; set style histogram clustered gap 1; set style fill solid 0.8 border -1"
        echo "set ylabel 'seconds'; set yrange [0:*]"
        echo "plot '$TMP/process' using 2:xtic(1) title 'glint (process wall time)' lc rgb '#d95f02', '' using 3 title 'Embree (load + build + render)' lc rgb '#1b9e77'"
    } >"$TMP/plot.gp"
    draw process.svg
fi

# --- scaling with triangles --------------------------------------------------------------------------
if rows "$DIR/meshscale.dat"; then
    for r in glint embree-mesh; do awk -v r="$r" '!/^#/ && $3 == r' "$DIR/meshscale.dat" >"$TMP/scale-$r"; done
    # scale_plot OUT TITLE YLABEL COLUMN LOGY KEY: glint and Embree against triangles
    scale_plot() {
        {
            head_of "$TMP/out.svg" "$2" "$6"
            echo "set logscale x; set format x '%.0s%c'; set xlabel 'triangles (log scale)'; set ylabel '$3'"
            if [ "$5" = 1 ]; then echo "set logscale y"; else echo "set yrange [0:*]"; fi
            printf 'plot "%s" using 2:%s with linespoints lw 2 pt 7 lc rgb "#d95f02" title "glint"' "$TMP/scale-glint" "$4"
            [ ! -s "$TMP/scale-embree-mesh" ] ||
                printf ', "%s" using 2:%s with linespoints lw 2 dt 2 pt 5 lc rgb "#1b9e77" title "Embree 3"' "$TMP/scale-embree-mesh" "$4"
            echo
        } >"$TMP/plot.gp"
        draw "$1"
    }
    scale_plot scale-nsray.svg "Cost per ray against triangles: the bunny, one thread" "ns per ray" 4 0 "top left"
    scale_plot scale-build.svg "BVH build time against triangles, one thread" "build seconds (log scale)" 5 1 "top left"
    scale_plot scale-memory.svg "Peak memory per triangle (peak RSS / triangles)" "bytes per triangle" 8 0 "top right"
fi

# --- equal error: RMSE against render time, glint and Cycles ------------------------------------------
if rows "$DIR/cycles.dat"; then
    for scene in $(awk '!/^#/ { print $1 }' "$DIR/cycles.dat" | sort -u); do
        {
            head_of "$TMP/out.svg" "RMSE against render time: $scene (lower left is better)" "top right"
            echo "set logscale xy; set xlabel 'render seconds (log scale)'; set ylabel 'RMSE (log scale)'"
            sep='plot '
            for th in $(awk -v s="$scene" '!/^#/ && $1 == s { print $2 }' "$DIR/cycles.dat" | sort -nu); do
                for r in glint cycles; do
                    awk -v s="$scene" -v t="$th" -v r="$r" '!/^#/ && $1 == s && $2 == t && $3 == r' "$DIR/cycles.dat" |
                        sort -g -k5 >"$TMP/cy-$r-$th"
                    [ -s "$TMP/cy-$r-$th" ] || continue
                    colour=$([ $r = glint ] && echo '#d95f02' || echo '#7570b3')
                    dash=$([ "$th" = 1 ] && echo 1 || echo 2)
                    col=$(awk 'NR == 1 { print ($8 == "nan" ? 7 : 8) }' "$TMP/cy-$r-$th")
                    printf '%s"%s" using 5:%s with linespoints lw 2 dt %s pt 7 lc rgb "%s" title "%s, %s thread%s"' \
                        "$sep" "$TMP/cy-$r-$th" "$col" "$dash" "$colour" "$r" "$th" "$([ "$th" = 1 ] || echo s)"
                    sep=', '
                done
            done
            echo
        } >"$TMP/plot.gp"
        draw "cycles-$scene.svg"
    done
fi
