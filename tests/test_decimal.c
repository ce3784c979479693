// test_decimal.c — decimal numbers read as float: the fast path (decimal_scan_float) and the whole reader
// (decimal_parse_float) give strtof's float bit for bit on edge cases and on a million random numbers of
// every shape (exporters' fixed point, round-trip floats, long mantissas, halfway cases, subnormals, the
// edge of the float range); the fast path takes the common shapes and leaves the rest; errors are classified;
// runs of digits read eight bytes at a time stop where the digits do.
#include "check.h"
#include "core/rng.h"
#include "io/decimal.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int mismatches;
static long fast_taken, fast_offered;

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

// s is a decimal number (the form decimal.h reads): both readers must agree with strtof, or refuse exactly
// what strtof cannot give as a finite float.
static void check_number(const char *s) {
    size_t n = strlen(s);
    char *stop;
    errno = 0;
    float want = strtof(s, &stop);
    if (stop != s + n) {
        if (mismatches++ < 10) fprintf(stderr, "  test bug: strtof does not read all of '%s'\n", s);
        return;
    }
    float got = 0.0f;
    decimal_status st = decimal_parse_float(s, n, &got);
    if (isinf(want)) {
        if (st != DECIMAL_RANGE && mismatches++ < 10) fprintf(stderr, "  '%s': status %d, expected out of range\n", s, (int)st);
    } else if (st != DECIMAL_OK || !same_bits(got, want)) {
        if (mismatches++ < 10)
            fprintf(stderr, "  '%s': status %d, got %a, strtof %a\n", s, (int)st, (double)got, (double)want);
    }
    // The fast path must not read past the text, and whatever it takes must be strtof's float too.
    float fast = 0.0f;
    const char *end = decimal_scan_float(s, s + n, &fast);
    fast_offered++;
    if (end == s + n) {
        fast_taken++;
        if (!same_bits(fast, want) && mismatches++ < 10)
            fprintf(stderr, "  fast path '%s': got %a, strtof %a\n", s, (double)fast, (double)want);
    } else if (end && mismatches++ < 10) {
        fprintf(stderr, "  fast path '%s' stopped %td bytes early\n", s, (s + n) - end);
    }
}

static void test_edge_cases(void) {
    static const char *const cases[] = {
        "0", "-0", "+0", "0.0", "-0.0", "00000", ".0", "0.", "+.5", "-.5", "5.", "1E+3", "1e-3", "1e+0", "1E0", "-1e-0",
        "0e99999", "0.0e-99999", "1e-45", "1.4e-45", "7e-46", "7.006492321624085e-46", "7.006492321624086e-46",
        "1.401298464324817e-45", "3.4028235e38", "3.40282346638528859811704183484516925440e+38", "3.4028234664e38",
        "3.4028235677973366e38", "3.4028235677973367e38", "3.40282357e38", "3.5e38", "1e39", "-1e39", "1e99999",
        "1.17549435e-38", "1.1754942e-38", "1.17549421e-38", "1.1754943508222875e-38", "2.5e-40", "-1e-320",
        "1e-400", "0.000000000000000000000000000000000001", "123456789012345678901234567890", "0.1", "0.2", "0.3",
        "0.30000000000000004", "16777216", "16777217", "16777218", "16777219", "33554434", "33554438",
        "9007199254740992", "9007199254740993", "18446744073709551615", "18446744073709551616",
        "9999999999999999999", "99999999999999999999", "1.00000005960464477539062500001",
        "1.000000059604644775390625", "1.0000000596046447753906249999", "0.500000029802322387695312500",
        "1234567890123456789e-10", "1234567890123456789e-30", "12345678901234567890e-10", "1e22", "1e23", "1e-22",
        "1e-23", "4e22", "123e20", "1.5e-20", "8388608.5", "8388609.5", "4194304.25", "4194304.75", "2097152.125",
        "0.000001", "-0.044779", "0.127940", "-0.037830", "1.000000", "0.999999940395355224609375",
        "0.99999997", "0.99999998", "0.99999999", "-12345.678901", "1e0000", "1e-0022", "000000000000000000001.5",
        "1.50000000000000000000", "1.500000000000000000001", "-9.999999e-39"};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) check_number(cases[i]);
    CHECK(mismatches == 0);
}

// Halfway cases, where a reader that rounds twice goes wrong: the exact midpoint between two neighbouring
// floats, and the decimals just above and below it.
static void test_halfway(rng *r) {
    char buf[128];
    for (int i = 0; i < 20000; i++) {
        uint32_t bits = rng_u32(r) % 0x7f000000u; // below the largest finite float's exponent
        float lo;
        memcpy(&lo, &bits, sizeof lo);
        float hi = nextafterf(lo, INFINITY);
        double mid = ((double)lo + (double)hi) / 2; // exact: a float's midpoint has 25 significant bits
        snprintf(buf, sizeof buf, "%.60g", mid);
        check_number(buf);
        snprintf(buf, sizeof buf, "%.17g", mid);
        check_number(buf);
        snprintf(buf, sizeof buf, "%.17g", nextafter(mid, INFINITY));
        check_number(buf);
        snprintf(buf, sizeof buf, "%.17g", nextafter(mid, 0));
        check_number(buf);
        snprintf(buf, sizeof buf, "%.9e", mid);
        check_number(buf);
    }
    // Integer midpoints above 2^24 have short decimals: the fast path sees them and must leave them.
    for (int i = 0; i < 20000; i++) {
        int e = 24 + (int)(rng_u32(r) % 29);
        uint64_t k = (UINT64_C(1) << 23) | (rng_u32(r) & 0x7fffffu);
        uint64_t mid = (2 * k + 1) << (e - 24); // halfway between k << (e - 23) and (k + 1) << (e - 23)
        snprintf(buf, sizeof buf, "%llu", (unsigned long long)mid);
        check_number(buf);
        snprintf(buf, sizeof buf, "-%llu", (unsigned long long)(mid + 1));
        check_number(buf);
        snprintf(buf, sizeof buf, "%llu", (unsigned long long)(mid - 1));
        check_number(buf);
    }
    CHECK(mismatches == 0);
}

// Random numbers of every shape a file may hold.
static void test_random(rng *r) {
    char buf[128];
    long taken_before = fast_taken, offered_before = fast_offered;
    // What exporters write (%.6f of coordinates): the fast path must take nearly all of them.
    for (int i = 0; i < 200000; i++) {
        double d = ((double)rng_u32(r) / 4294967296.0 * 2.0 - 1.0) * pow(10.0, (double)(rng_u32(r) % 9) - 4.0);
        snprintf(buf, sizeof buf, "%.6f", d);
        check_number(buf);
    }
    CHECK(fast_taken - taken_before > (fast_offered - offered_before) * 999 / 1000);
    for (int i = 0; i < 600000; i++) {
        uint32_t bits = rng_u32(r);
        float f;
        memcpy(&f, &bits, sizeof f);
        if (!isfinite(f)) f = 1.5f;
        double d = ((double)rng_u32(r) / 4294967296.0 * 2.0 - 1.0) * pow(10.0, (double)(rng_u32(r) % 61) - 30.0);
        switch (i % 8) {
        case 0: snprintf(buf, sizeof buf, "%.9g", (double)f); break;  // any float, round trip
        case 1: snprintf(buf, sizeof buf, "%.17g", d); break;         // more digits than a float holds
        case 2: snprintf(buf, sizeof buf, "%.8e", (double)f); break;
        case 3: snprintf(buf, sizeof buf, "%d", (int)rng_u32(r)); break;
        case 4: snprintf(buf, sizeof buf, "%.3g", d); break;
        case 5: snprintf(buf, sizeof buf, "%.*f", (int)(rng_u32(r) % 12), d); break;
        case 6: snprintf(buf, sizeof buf, "%.*e", (int)(rng_u32(r) % 25), (double)f); break;
        default: {
            // Random digits, point and exponent, leading zeros included.
            int k = 0, len = 1 + (int)(rng_u32(r) % 26), point = (int)(rng_u32(r) % (uint32_t)(len + 2)) - 1;
            if (rng_u32(r) % 2) buf[k++] = rng_u32(r) % 2 ? '-' : '+';
            for (int j = 0; j < len; j++) {
                if (j == point) buf[k++] = '.';
                buf[k++] = (char)('0' + (rng_u32(r) % 4 == 0 ? 0 : rng_u32(r) % 10));
            }
            if (point == len) buf[k++] = '.';
            if (rng_u32(r) % 2) k += snprintf(buf + k, sizeof buf - (size_t)k, "e%d", (int)(rng_u32(r) % 101) - 50);
            buf[k] = '\0';
        }
        }
        check_number(buf);
    }
    CHECK(mismatches == 0);
}

// Every float in a range of bit patterns near 1, and near the bottom of the normal range, round trips.
static void test_round_trips(void) {
    char buf[64];
    for (uint32_t bits = 0x3f800000u - 50000; bits < 0x3f800000u + 50000; bits++) {
        float f;
        memcpy(&f, &bits, sizeof f);
        snprintf(buf, sizeof buf, "%.9g", (double)f);
        check_number(buf);
    }
    for (uint32_t bits = 0x00800000u - 2000; bits < 0x00800000u + 2000; bits++) {
        float f;
        memcpy(&f, &bits, sizeof f);
        snprintf(buf, sizeof buf, "%.9g", (double)f);
        check_number(buf);
    }
    CHECK(mismatches == 0);
}

// What is not a decimal number, with its status, and where the fast path stops on a number followed by more.
static void test_refusals(void) {
    static const struct { const char *text; decimal_status st; } bad[] = {
        {"", DECIMAL_MALFORMED}, {"-", DECIMAL_MALFORMED}, {"+", DECIMAL_MALFORMED}, {".", DECIMAL_MALFORMED},
        {"-.", DECIMAL_MALFORMED}, {"e5", DECIMAL_MALFORMED}, {"1e", DECIMAL_MALFORMED}, {"1e+", DECIMAL_MALFORMED},
        {"1e-", DECIMAL_MALFORMED}, {"1.5.2", DECIMAL_MALFORMED}, {"1,5", DECIMAL_MALFORMED}, {"0x1p3", DECIMAL_MALFORMED},
        {"--1", DECIMAL_MALFORMED}, {"1 ", DECIMAL_MALFORMED}, {" 1", DECIMAL_MALFORMED}, {"1e5x", DECIMAL_MALFORMED},
        {"abc", DECIMAL_MALFORMED}, {"nan", DECIMAL_NOT_FINITE}, {"-NaN", DECIMAL_NOT_FINITE}, {"nan(123)", DECIMAL_NOT_FINITE},
        {"inf", DECIMAL_NOT_FINITE}, {"-Infinity", DECIMAL_NOT_FINITE}, {"1.#INF", DECIMAL_NOT_FINITE},
        {"-1.#IND", DECIMAL_NOT_FINITE}, {"1.#QNAN", DECIMAL_NOT_FINITE}, {"1e39", DECIMAL_RANGE}, {"-4e38", DECIMAL_RANGE},
        {"1e100000000000", DECIMAL_RANGE}, {"infinite", DECIMAL_MALFORMED}, {"nano", DECIMAL_MALFORMED}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        float f = 42.0f;
        decimal_status st = decimal_parse_float(bad[i].text, strlen(bad[i].text), &f);
        CHECK(st == bad[i].st);
        if (st != bad[i].st) fprintf(stderr, "  '%s': status %d, expected %d\n", bad[i].text, (int)st, (int)bad[i].st);
        CHECK(f == 42.0f);
    }
    // The fast path stops where the number does and leaves the rest to its caller.
    static const struct { const char *text; int stop; float value; } partial[] = {
        {"1.5 2", 3, 1.5f}, {"-2\n", 2, -2.0f}, {"3e2/4", 3, 300.0f}, {"7x", 1, 7.0f}, {"0.25\r\n", 4, 0.25f},
        {"1.#INF", 2, 1.0f}, {"12/", 2, 12.0f}};
    for (size_t i = 0; i < sizeof partial / sizeof partial[0]; i++) {
        const char *s = partial[i].text;
        float f = 0.0f;
        const char *end = decimal_scan_float(s, s + strlen(s), &f);
        CHECK(end == s + partial[i].stop && f == partial[i].value);
    }
    // It never reads past `end`: the same bytes cut short read as the shorter number.
    const char *s = "123.456e7";
    float f = 0.0f;
    CHECK(decimal_scan_float(s, s + 5, &f) == s + 5 && f == 123.4f);
    CHECK(decimal_scan_float(s, s + 8, &f) == NULL); // "123.456e": an exponent without digits
    // What it leaves to decimal_parse_float.
    static const char *const slow[] = {"nan", "inf", "-", ".", "e1", "1e", "1e+", "12345678901234567890", "1e23",
                                       "1e-23", "1e12345", "16777217", "9007199254740993", "1e-40"};
    for (size_t i = 0; i < sizeof slow / sizeof slow[0]; i++)
        CHECK(decimal_scan_float(slow[i], slow[i] + strlen(slow[i]), &f) == NULL);
}

// Runs of digits, read eight bytes at a time where eight can be read: every length from 0 to 30, ending at
// `end` or on each kind of byte that is not a digit (those just below and above '0'..'9' in ASCII, and bytes
// whose high nibble is 3 or that carry when 6 is added), at every distance from `end`.
static void test_digit_runs(rng *r) {
    static const unsigned char stops[] = {' ', '\n', '.', '/', '\0', 0x2a, 0x2f, 0x3a, 0x3f, 0x40, 0x20, 0xfa, 0xff, 0xb0, 0x39 + 0x80, 'e'};
    char buf[64];
    int bad = 0;
    for (int len = 0; len <= 30; len++)
        for (size_t s = 0; s <= sizeof stops; s++)     // s == sizeof stops: the run ends at `end`
            for (int tail = 0; tail < 12; tail++) {    // bytes after the stop that may be read
                int k = 0;
                for (int i = 0; i < len; i++) buf[k++] = (char)('0' + rng_u32(r) % 10);
                if (s < sizeof stops) buf[k++] = (char)stops[s];
                for (int i = 0; i < tail; i++) buf[k++] = (char)(rng_u32(r) % 256);
                const char *end = s < sizeof stops ? buf + k : buf + len;
                uint64_t want = 7, got = 7; // a value already there is carried on
                for (int i = 0; i < len; i++) want = want * 10 + (uint64_t)(buf[i] - '0');
                const char *stop = decimal_scan_digits(buf, end, &got);
                if (stop != buf + len || got != want) {
                    if (bad++ < 5) fprintf(stderr, "  run of %d digits, stop byte %zu, %d bytes after: read %td\n", len, s, tail, stop - buf);
                }
            }
    CHECK(bad == 0);
}

int main(void) {
    rng r = rng_for_sample(11, 4, 0);
    test_edge_cases();
    test_halfway(&r);
    test_random(&r);
    test_round_trips();
    test_refusals();
    test_digit_runs(&r);
    printf("fast path took %ld of %ld numbers\n", fast_taken, fast_offered);
    return check_summary();
}
