// sobol.c — the generator matrices of the first Sobol' dimensions, from Joe & Kuo's direction numbers (the
// sampler's draw, rng_float's path for it, is core/rng.c).
#include "core/sobol.h"

// Joe and Kuo's primitive polynomials and initial direction numbers for dimensions 2-10 of their table
// new-joe-kuo-6.21201 (S. Joe and F. Y. Kuo, "Constructing Sobol sequences with better two-dimensional
// projections", SIAM J. Sci. Comput. 30 (2008) 2635-2654; the file at https://web.maths.unsw.edu.au/~fkuo/sobol/),
// typed from its first rows "d s a m_i": the polynomial x^s + a_1 x^(s-1) + ... + a_(s-1) x + 1 has its
// middle coefficients a_1 ... a_(s-1) as the bits of `a` (a_1 the highest), and m_1 ... m_s start the recurrence.
// Dimension 1 of the table (here 0) is the van der Corput sequence: every m_k = 1.
static const struct {
    int s, a;
    uint32_t m[5];
} joe_kuo[SOBOL_DIMENSIONS - 1] = {
    {1, 0, {1}},              // x + 1
    {2, 1, {1, 3}},           // x^2 + x + 1
    {3, 1, {1, 3, 1}},        // x^3 + x + 1
    {3, 2, {1, 1, 1}},        // x^3 + x^2 + 1
    {4, 1, {1, 1, 3, 3}},     // x^4 + x + 1
    {4, 4, {1, 3, 5, 13}},    // x^4 + x^3 + 1
    {5, 2, {1, 1, 5, 5, 17}}, // x^5 + x^2 + 1
    {5, 4, {1, 1, 5, 5, 5}},  // x^5 + x^3 + 1
    {5, 7, {1, 1, 7, 11, 19}}, // x^5 + x^3 + x^2 + x + 1
};

// Bratley and Fox's recurrence (ACM TOMS algorithm 659) on the m_k, odd integers below 2^k:
// m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^(s-1) a_(s-1) m_(k-s+1) ^ 2^s m_(k-s) ^ m_(k-s); column k - 1
// (index bit k - 1) is m_k / 2^k as a 32-bit fraction.
void sobol_matrix(int dim, uint32_t columns[32]) {
    uint32_t m[33] = {0};
    if (dim == 0) {
        for (int k = 1; k <= 32; k++) m[k] = 1;
    } else {
        int s = joe_kuo[dim - 1].s, a = joe_kuo[dim - 1].a;
        for (int k = 1; k <= s; k++) m[k] = joe_kuo[dim - 1].m[k - 1];
        for (int k = s + 1; k <= 32; k++) {
            uint64_t v = ((uint64_t)m[k - s] << s) ^ m[k - s];
            for (int j = 1; j < s; j++)
                if ((a >> (s - 1 - j)) & 1) v ^= (uint64_t)m[k - j] << j;
            m[k] = (uint32_t)v; // below 2^k <= 2^32
        }
    }
    for (int k = 1; k <= 32; k++) columns[k - 1] = k == 32 ? m[k] : m[k] << (32 - k);
}

uint32_t sobol_point(uint32_t index, int dim) {
    uint32_t columns[32], v = 0;
    sobol_matrix(dim, columns);
    for (int k = 0; index; k++, index >>= 1)
        if (index & 1u) v ^= columns[k];
    return v;
}
