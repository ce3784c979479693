# stats.bash — the statistics bench/run.sh and bench/ab.sh print (sourced): the median of numbers, and the
# distribution-free confidence interval of that median, so that a ratio's table says how far the shared
# machine's scatter leaves it uncertain.

# median: the median of the numbers on standard input, one per line (nan when there are none).
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "nan"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.4g\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# median_interval: for the numbers on standard input, "LO-HI (C %)": the interval between the k-th smallest and
# the k-th largest, with k the largest for which it holds the true median with a probability C of at least
# 90 % whatever the numbers' distribution (the count below the median is binomial, n and 1/2); nan for fewer
# than five numbers, too few for 90 %.
median_interval() {
    sort -g | awk '{ v[NR] = $1 } END {
        n = NR; p = 0.5 ^ n; below = p; k = 0
        # below: P(at most j of the n fall under the median); the interval [v[j + 1], v[n - j]] misses it with
        # probability 2 below.
        for (j = 0; 2 * below <= 0.10 && j < n / 2; j++) { k = j + 1; miss = 2 * below; p = p * (n - j) / (j + 1); below += p }
        if (k == 0) { print "nan"; exit }
        printf "%.3f-%.3f (%d %%)\n", v[k], v[n - k + 1], int(100 * (1 - miss))
    }'
}
