// check.h — the tests' assertions: each CHECK counts, failures print file:line, and check_summary()
// prints "N passed, M failed" and gives the exit code.
#ifndef GLINT_CHECK_H
#define GLINT_CHECK_H

#include <math.h>
#include <stdio.h>

static int check_passed, check_failed;

#define CHECK(cond)                                                                                      \
    do {                                                                                                 \
        if (cond) check_passed++;                                                                        \
        else { check_failed++; fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); } \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                            \
    do {                                                                                                 \
        double check_a_ = (double)(a), check_b_ = (double)(b);                                           \
        if (fabs(check_a_ - check_b_) <= (double)(tol)) check_passed++;                                  \
        else {                                                                                           \
            check_failed++;                                                                              \
            fprintf(stderr, "%s:%d: %s = %.9g, expected %s = %.9g (tolerance %g)\n", __FILE__, __LINE__, #a, \
                    check_a_, #b, check_b_, (double)(tol));                                              \
        }                                                                                                \
    } while (0)

static inline int check_summary(void) {
    printf("%d passed, %d failed\n", check_passed, check_failed);
    return check_failed ? 1 : 0;
}

#endif
