// decimal.c — any decimal token read as float: the exact fast path when it applies, strtof otherwise.
#include "io/decimal.h"

#include <math.h>
#include <stdlib.h>

const uint32_t decimal_pow10_u32[9] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};

const double decimal_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// |strtof| of a NUL-terminated copy of the token: the rare numbers the exact paths cannot take. False when
// there is no memory for the copy of a long token.
static bool slow_float(const char *s, size_t n, float *out) {
    char small[128];
    char *buf = n < sizeof small ? small : malloc(n + 1);
    if (!buf) return false;
    memcpy(buf, s, n);
    buf[n] = '\0';
    *out = fabsf(strtof(buf, NULL));
    if (buf != small) free(buf);
    return true;
}

// Whether s starts with the lower-case word w, ignoring case.
static bool starts_with_word(const char *s, size_t n, const char *w) {
    size_t k = strlen(w);
    if (n < k) return false;
    for (size_t i = 0; i < k; i++)
        if ((s[i] | 0x20) != w[i]) return false;
    return true;
}

// The C library's spellings of NaN and infinity: nan, nan(...), inf, infinity, in any case.
static bool is_nan_or_inf(const char *s, size_t n) {
    if (starts_with_word(s, n, "nan")) return n == 3 || s[3] == '(';
    return (n == 3 && starts_with_word(s, n, "inf")) || (n == 8 && starts_with_word(s, n, "infinity"));
}

static inline bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Beyond the fast path: any number of digits (the first 17 significant ones kept, the rest only checked
// for being zeros) and any exponent; exact in double when the digits kept are all there is and the power
// of ten is within 1e±22 (Clinger's fast path), otherwise by strtof.
decimal_status decimal_parse_float(const char *s, size_t n, float *out) {
    float fast;
    if (n > 0 && decimal_scan_float(s, s + n, &fast) == s + n) {
        *out = fast;
        return DECIMAL_OK;
    }
    size_t i = 0;
    bool neg = false;
    if (i < n && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
    if (is_nan_or_inf(s + i, n - i)) return DECIMAL_NOT_FINITE;
    uint64_t m = 0;
    int exp10 = 0;
    bool digits = false, exact = true;
    for (; i < n && is_digit(s[i]); i++) {
        digits = true;
        if (m < UINT64_C(100000000000000000)) m = m * 10 + (uint64_t)(s[i] - '0');
        else {
            if (exp10 < 100000) exp10++;
            if (s[i] != '0') exact = false;
        }
    }
    if (i < n && s[i] == '.') {
        for (i++; i < n && is_digit(s[i]); i++) {
            digits = true;
            if (m < UINT64_C(100000000000000000)) {
                m = m * 10 + (uint64_t)(s[i] - '0');
                exp10--;
            } else if (s[i] != '0') exact = false;
        }
    }
    if (digits && i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        bool eneg = false;
        if (i < n && (s[i] == '+' || s[i] == '-')) eneg = s[i++] == '-';
        if (i == n || !is_digit(s[i])) return DECIMAL_MALFORMED;
        int e = 0;
        for (; i < n && is_digit(s[i]); i++)
            if (e < 100000) e = e * 10 + (s[i] - '0');
        exp10 += eneg ? -e : e;
    }
    if (!digits || i != n) {
        // Microsoft's C library prints NaN and infinity as 1.#IND, 1.#QNAN, 1.#INF.
        return memchr(s, '#', n) ? DECIMAL_NOT_FINITE : DECIMAL_MALFORMED;
    }
    float f;
    if (m == 0) f = 0.0f;
    else if (exact && m <= (UINT64_C(1) << 53) && exp10 >= -22 && exp10 <= 22) {
        double d = exp10 < 0 ? (double)m / decimal_pow10[-exp10] : (double)m * decimal_pow10[exp10];
        f = (float)d;
        if (decimal_double_to_float_unsafe(d) && !slow_float(s, n, &f)) return DECIMAL_NOMEM;
    } else if (!slow_float(s, n, &f)) return DECIMAL_NOMEM;
    if (!isfinite(f)) return DECIMAL_RANGE;
    *out = neg ? -f : f;
    return DECIMAL_OK;
}
