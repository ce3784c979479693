// decimal.h — decimal numbers in text read as float, rounded exactly as strtof rounds them (to nearest,
// ties to even), without a locale and without copying the text.
//
// The form read is [+-](digits[.digits] | .digits)[(e|E)[+-]digits]; NaN and infinity spellings, hexadecimal
// and anything else are refused. decimal_scan_float is the fast path that the OBJ reader calls for every
// coordinate: it takes the common numbers (at most 19 digits, a power of ten within 1e±22) and reads them
// with Clinger's exact method; decimal_parse_float reads any token, falling back to strtof for the rest.
// Both give strtof's result bit for bit (tests/test_decimal.c compares them with strtof).
#ifndef GLINT_DECIMAL_H
#define GLINT_DECIMAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/// How reading a number went.
typedef enum decimal_status {
    DECIMAL_OK,
    DECIMAL_MALFORMED,  ///< not a decimal number
    DECIMAL_NOT_FINITE, ///< a spelling of NaN or infinity (C's nan, inf, infinity; Microsoft's 1.#INF, 1.#IND)
    DECIMAL_RANGE,      ///< its magnitude rounds beyond the largest float
    DECIMAL_NOMEM       ///< no memory for the copy strtof needs of a long token
} decimal_status;

/// Reads the whole token s[0, n) as a float, exactly as strtof would round it.
decimal_status decimal_parse_float(const char *s, size_t n, float *out);

/// Powers of ten that a double holds exactly (10^22 is the last).
extern const double decimal_pow10[23];

/// Whether rounding the double d to float could differ from rounding the exact decimal that d is the
/// correctly rounded double of: only when d lies exactly halfway between two floats, or is so small that
/// float would be subnormal (checked too, to be safe).
static inline bool decimal_double_to_float_unsafe(double d) {
    double a = d < 0 ? -d : d;
    if (a < 0x1p-126) return true;
    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    return (bits & ((UINT64_C(1) << 29) - 1)) == (UINT64_C(1) << 28);
}

/// Powers of ten as integers, 10^0 to 10^8.
extern const uint32_t decimal_pow10_u32[9];

/// Reads the run of decimal digits at p (before end), appending them to *value (*value * 10^k + their
/// value, modulo 2^64) and returns its end; the run's length is the returned pointer minus p. Eight bytes
/// at a time where they can be read (little-endian machines): no branch per digit to mispredict.
static inline const char *decimal_scan_digits(const char *p, const char *end, uint64_t *value) {
    uint64_t m = *value;
#if defined(__GNUC__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    while (end - p >= 8) {
        uint64_t w;
        memcpy(&w, p, sizeof w);
        // A byte is a digit when its high nibble is 3 and adding 6 keeps it so; a carry out of a byte that is
        // not a digit can only spoil the bytes after it, which are not looked at.
        uint64_t not_digit = ((w & UINT64_C(0xf0f0f0f0f0f0f0f0)) ^ UINT64_C(0x3030303030303030)) |
                             (((w + UINT64_C(0x0606060606060606)) & UINT64_C(0xf0f0f0f0f0f0f0f0)) ^ UINT64_C(0x3030303030303030));
        int k = not_digit ? __builtin_ctzll(not_digit) >> 3 : 8;
        if (k == 0) break;
        // The k digits moved to the top, zeros (leading zeros) below, then summed in pairs, fours, eights.
        uint64_t d = w << (64 - 8 * k);
        d = ((d & UINT64_C(0x0f0f0f0f0f0f0f0f)) * 2561) >> 8;
        d = ((d & UINT64_C(0x00ff00ff00ff00ff)) * 6553601) >> 16;
        d = ((d & UINT64_C(0x0000ffff0000ffff)) * UINT64_C(42949672960001)) >> 32;
        m = m * decimal_pow10_u32[k] + d;
        p += k;
        if (k < 8) {
            *value = m;
            return p;
        }
    }
#endif
    while (p < end && (unsigned char)(*p - '0') < 10) m = m * 10 + (uint64_t)(*p++ - '0');
    *value = m;
    return p;
}

/// Fast path: reads the number that starts at p (p < end) and returns the end of it, or NULL when the text
/// there is not a number this path takes (then nothing is written, and decimal_parse_float of the token
/// decides: it may still be a number, or an error). The caller checks what follows the number.
static inline const char *decimal_scan_float(const char *p, const char *end, float *out) {
    bool neg = *p == '-';
    if (*p == '-' || *p == '+') p++;
    uint64_t m = 0;
    const char *first = p;
    p = decimal_scan_digits(p, end, &m);
    int exp10 = 0;
    bool point = p < end && *p == '.';
    if (point) {
        const char *frac = ++p;
        p = decimal_scan_digits(p, end, &m);
        exp10 = -(int)(p - frac);
    }
    // Up to 19 digits m is exact (10^19 < 2^64); longer mantissas wrapped around and go to the slow path.
    ptrdiff_t digits = (p - first) - point;
    if (digits == 0 || digits > 19) return NULL;
    if (p < end && (*p | 0x20) == 'e') {
        p++;
        bool eneg = p < end && *p == '-';
        if (p < end && (*p == '-' || *p == '+')) p++;
        const char *e0 = p;
        int e = 0;
        while (p < end && (unsigned char)(*p - '0') < 10 && p - e0 < 4) e = e * 10 + (*p++ - '0');
        if (p == e0 || (p < end && (unsigned char)(*p - '0') < 10)) return NULL; // no digits, or more than 4
        exp10 += eneg ? -e : e;
    }
    float f;
    if (m == 0) f = 0.0f;
    else {
        // Clinger: m and 10^|exp10| are exact doubles, so one division or product rounds once, correctly.
        if (m > (UINT64_C(1) << 53) || exp10 < -22 || exp10 > 22) return NULL;
        double d = exp10 < 0 ? (double)m / decimal_pow10[-exp10] : (double)m * decimal_pow10[exp10];
        if (decimal_double_to_float_unsafe(d)) return NULL;
        f = (float)d;
    }
    *out = neg ? -f : f;
    return p;
}

#endif
