// obj_fast.c — the OBJ reader's fast paths and its readers of a file: plain v, vn, vt and f lines read in one pass
// over their bytes (anything else goes to the statements of obj_statements.c), a file read block by block, and a
// large file pre-scanned on several threads while one stores what they read, in the file's order.
#include "core/array.h"
#include "core/prefetch.h"
#include "core/thread_pool.h"
#include "io/decimal.h"
#include "io/obj_parser.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/// Bytes of an OBJ file read at a time: small enough to stay in the cache while it is parsed.
enum { OBJ_READ_BLOCK = 256 << 10 };

// ---------------------------------------------------------------------------------------------------------
// Fast paths: the plain lines that make up nearly all of a large file (`v`, `vn`, `vt` with numbers, `f`
// with corners v, v/vt, v//vn or v/vt/vn) read in one pass over their bytes, without cutting the line into
// tokens first. Whatever else a line holds (a comment, an unusual number, an index out of range, too many
// numbers, any error) sends it, untouched, to the statements (obj_statements.c), which read it again and say what is
// wrong: a fast path only ever accepts what they accept, and stores it through the same functions.

typedef enum fast_result {
    FAST_NO,  // not a line for a fast path: nothing was done, read it as a statement
    FAST_OK,  // read and stored
    FAST_FAIL // stored part of it and failed (out of memory, too many triangles): the message is set
} fast_result;

// Up to `max` numbers to the end of the line; *stop gets the end of the line (its '\n', or `end`).
static inline bool fast_numbers(const char *p, const char *end, float *v, int max, int *count, const char **stop) {
    int k = 0;
    for (;;) {
        while (p < end && obj_is_space(*p)) p++;
        if (p == end || *p == '\n') break;
        if (k == max || !(p = decimal_scan_float(p, end, &v[k]))) return false;
        k++;
        if (p < end && !obj_is_space(*p) && *p != '\n') return false; // "1.5x", "1.#INF", "2#comment"
    }
    *count = k;
    *stop = p;
    return true;
}

// A face index as written (1-based, or negative: relative) into *raw; NULL for anything else: no digits, more
// than 10 digits, or 0.
static inline const char *fast_index_raw(const char *p, const char *end, int64_t *raw) {
    bool neg = p < end && *p == '-';
    p += neg;
    const char *first = p;
    uint64_t v = 0;
    p = decimal_scan_digits(p, end, &v);
    if (p == first || p - first > 10 || v == 0) return NULL;
    *raw = neg ? -(int64_t)v : (int64_t)v;
    return p;
}

// A raw index into `count` elements -> 0-based; false when out of range.
static inline bool fast_index_resolve(int64_t raw, size_t count, int32_t *out) {
    uint64_t v = raw < 0 ? (uint64_t)-raw : (uint64_t)raw;
    if (v > count) return false;
    *out = (int32_t)(raw < 0 ? count - v : v - 1);
    return true;
}

// One face corner as written, v, v/vt, v//vn or v/vt/vn: raw[0], raw[1], raw[2] its indices (0: absent); NULL for
// anything else, including what follows it on the line ("1/2/3/4", "1x", "1#comment").
static inline const char *fast_corner_raw(const char *p, const char *end, int64_t raw[3]) {
    raw[1] = raw[2] = 0;
    if (!(p = fast_index_raw(p, end, &raw[0]))) return NULL;
    if (p < end && *p == '/') {
        p++;
        if ((p == end || *p != '/') && !(p = fast_index_raw(p, end, &raw[1]))) return NULL;
        if (p < end && *p == '/' && !(p = fast_index_raw(p + 1, end, &raw[2]))) return NULL;
    }
    if (p < end && !obj_is_space(*p) && *p != '\n') return NULL;
    return p;
}

// A raw corner resolved against the mesh read so far; false when an index is out of range.
static inline bool fast_corner_resolve(const mesh *m, const int64_t raw[3], obj_corner *k) {
    k->t = k->n = -1;
    return fast_index_resolve(raw[0], m->position_count, &k->v) &&
           (raw[1] == 0 || fast_index_resolve(raw[1], m->uv_count, &k->t)) &&
           (raw[2] == 0 || fast_index_resolve(raw[2], m->normal_count, &k->n));
}

// The corners of a face into ps->corners; *stop gets the end of the line.
static bool fast_corners(obj_parser *ps, const char *p, const char *end, size_t *count, const char **stop) {
    const mesh *m = &ps->model->mesh;
    size_t n = 0;
    for (;;) {
        while (p < end && obj_is_space(*p)) p++;
        if (p == end || *p == '\n') break;
        if (n == OBJ_MAX_FACE_CORNERS ||
            (n == ps->corner_cap && !array_reserve((void **)&ps->corners, &ps->corner_cap, n + 1, sizeof *ps->corners)))
            return false;
        int64_t raw[3];
        if (!(p = fast_corner_raw(p, end, raw)) || !fast_corner_resolve(m, raw, &ps->corners[n++])) return false;
    }
    *count = n;
    *stop = p;
    return n >= 3;
}

// Adds the oldest queued triangle, as the line that read it.
static bool add_oldest_queued(obj_parser *ps) {
    const obj_queued_triangle *t = &ps->queue[ps->queue_head];
    ps->queue_head = (ps->queue_head + 1) % OBJ_QUEUED_TRIANGLES;
    ps->queue_count--;
    long line = ps->rep.line;
    ps->rep.line = t->line;
    bool ok = obj_triangle_face(ps, t->k);
    ps->rep.line = line;
    return ok;
}

// Adds every queued triangle, in the order of their lines: before any other line is read, so that triangles,
// warnings and errors come in the order of the file.
static bool add_queued(obj_parser *ps) {
    while (ps->queue_count > 0)
        if (!add_oldest_queued(ps)) return false;
    return true;
}

// Queues a triangle read on the current line and starts fetching its corners; the oldest is added when
// the queue is full.
static bool queue_triangle(obj_parser *ps, const obj_corner *k) {
    if (ps->queue_count == OBJ_QUEUED_TRIANGLES && !add_oldest_queued(ps)) return false;
    obj_queued_triangle *t = &ps->queue[(ps->queue_head + ps->queue_count++) % OBJ_QUEUED_TRIANGLES];
    memcpy(t->k, k, sizeof t->k);
    t->line = ps->rep.line;
    const vec3 *pos = ps->model->mesh.positions;
    for (int i = 0; i < 3; i++) prefetch_read(&pos[k[i].v]);
    return true;
}

/// The lines the fast paths read.
typedef enum fast_kind { FAST_VERTEX, FAST_NORMAL, FAST_TEXCOORD, FAST_FACE, FAST_OTHER } fast_kind;

static inline fast_kind fast_kind_of(const char *s, const char *end) {
    if (end - s < 3) return FAST_OTHER;
    if (s[0] == 'v' && obj_is_space(s[1])) return FAST_VERTEX;
    if (s[0] == 'f' && obj_is_space(s[1])) return FAST_FACE;
    if (s[0] == 'v' && s[1] == 'n' && obj_is_space(s[2])) return FAST_NORMAL;
    if (s[0] == 'v' && s[1] == 't' && obj_is_space(s[2])) return FAST_TEXCOORD;
    return FAST_OTHER;
}

// The numbers of a v, vn or vt line at s (as many as its kind takes); *stop gets the end of the line.
static inline bool fast_line_numbers(fast_kind kind, const char *s, const char *end, float *v, int *count,
                                     const char **stop) {
    if (kind == FAST_VERTEX) return fast_numbers(s + 2, end, v, 7, count, stop) && *count >= 3;
    if (kind == FAST_NORMAL) return fast_numbers(s + 3, end, v, 3, count, stop) && *count == 3;
    return fast_numbers(s + 3, end, v, 3, count, stop) && *count >= 1;
}

// Stores what a fast path read: a v, vn or vt line's numbers, or a face of `corners` corners in ps->corners.
static fast_result fast_store(obj_parser *ps, fast_kind kind, const float *v, int count, size_t corners) {
    if (kind == FAST_FACE && corners == 3) return queue_triangle(ps, ps->corners) ? FAST_OK : FAST_FAIL;
    if (!add_queued(ps)) return FAST_FAIL;
    bool ok = kind == FAST_FACE     ? obj_triangulate(ps, corners)
              : kind == FAST_VERTEX ? obj_add_position(ps, v)
              : kind == FAST_NORMAL ? obj_add_normal(ps, v)
                                    : obj_add_texcoord(ps, v, count);
    return ok ? FAST_OK : FAST_FAIL;
}

// The line at s by a fast path, if it is one of theirs; *next gets the start of the next line.
static fast_result fast_line(obj_parser *ps, const char *s, const char *end, const char **next) {
    fast_kind kind = fast_kind_of(s, end);
    if (kind == FAST_OTHER) return FAST_NO;
    const char *stop;
    float v[7];
    int count = 0;
    size_t corners = 0;
    bool ok = kind == FAST_FACE ? fast_corners(ps, s + 2, end, &corners, &stop)
                                : fast_line_numbers(kind, s, end, v, &count, &stop);
    // A line longer than the limit is an error however well formed: the statement reader says so.
    if (!ok || (size_t)(stop - s) > OBJ_MAX_LINE_BYTES) return FAST_NO;
    *next = stop < end ? stop + 1 : end;
    return fast_store(ps, kind, v, count, corners);
}

// Reads a line as a statement (the form obj_read_line calls).
static bool statement_line(void *state, obj_cursor *c) { return obj_statement(state, c); }

// Every line of (a part of) an OBJ text, counting on from ps->rep.line: by a fast path when it takes the
// line, else as a statement.
bool obj_lines(obj_parser *ps, const char *text, size_t length) {
    const char *s = text, *end = text + length;
    bool fast = !(ps->opt && ps->opt->statements_only);
    while (s < end) {
        ps->rep.line++;
        fast_result r = fast ? fast_line(ps, s, end, &s) : FAST_NO;
        if (r == FAST_FAIL ||
            (r == FAST_NO && (!add_queued(ps) || !obj_read_line(s, end, &ps->rep, statement_line, ps, &s))))
            return false;
    }
    return add_queued(ps);
}

// ---------------------------------------------------------------------------------------------------------
// One thread: the file block by block

// The buffer of a line that fills it, doubled up to one byte more than a line may hold. False when it already
// holds that (the line is too long: *errnum stays 0) or memory runs out (*errnum ENOMEM).
static bool grow_line_buffer(char **buf, size_t *cap, int *errnum) {
    if (*cap > OBJ_MAX_LINE_BYTES) return false;
    size_t bigger = *cap > OBJ_MAX_LINE_BYTES / 2 ? OBJ_MAX_LINE_BYTES + 1 : *cap * 2;
    char *grown = realloc(*buf, bigger);
    if (!grown) {
        *errnum = ENOMEM;
        return false;
    }
    *buf = grown;
    *cap = bigger;
    return true;
}

// A line longer than the limit, `length` bytes of it read: an error that gives its length, so read on to its end
// (through buf). Always false.
static bool line_too_long_read_on(obj_parser *ps, FILE *f, char *buf, size_t cap, size_t length) {
    char *nl = NULL;
    for (size_t got = 1; !nl && got > 0 && length <= OBJ_MAX_FILE_BYTES;) {
        got = fread(buf, 1, cap, f);
        nl = memchr(buf, '\n', got);
        length += nl ? (size_t)(nl - buf) : got;
    }
    ps->rep.line++;
    return obj_line_too_long(&ps->rep, length);
}

// Reads the open OBJ file f block by block and parses the complete lines of each block as it arrives, exactly
// as obj_parse parses them: a large file is never held whole, which spares copying it into fresh memory (a
// page fault every 4 KiB) and reading it back from far away. False on a parse failure (message set, *errnum
// 0) or a read failure (*errnum: the read's errno, EFBIG past OBJ_MAX_FILE_BYTES, ENOMEM).
static bool obj_read_stream(obj_parser *ps, FILE *f, int *errnum) {
    *errnum = 0;
    size_t cap = OBJ_READ_BLOCK, have = 0, total = 0; // have: bytes of buf not parsed yet, a part of a line
    char *buf = malloc(cap);
    bool ok = buf != NULL, eof = false;
    if (!ok) *errnum = ENOMEM;
    while (ok && !eof) {
        if (have == cap && !grow_line_buffer(&buf, &cap, errnum)) { // the buffer is one unfinished line
            ok = !*errnum; // too long: said below
            break;
        }
        size_t got = fread(buf + have, 1, cap - have, f);
        eof = got < cap - have;
        if (eof && ferror(f)) *errnum = errno ? errno : EIO;
        else if ((total += got) > OBJ_MAX_FILE_BYTES) *errnum = EFBIG;
        if (*errnum) {
            ok = false;
            break;
        }
        have += got;
        // Parse up to the last line end; at the end of the file, the last line too.
        size_t upto = have;
        while (!eof && upto > 0 && buf[upto - 1] != '\n') upto--;
        ok = obj_lines(ps, buf, upto);
        memmove(buf, buf + upto, have - upto);
        have -= upto;
    }
    if (ok && !eof) ok = line_too_long_read_on(ps, f, buf, cap, have);
    free(buf);
    return ok;
}

// ---------------------------------------------------------------------------------------------------------
// On several threads: a large file is read in blocks; while one thread stores the lines of a block (the steps
// above, in the file's order: the same mesh, warnings and errors as reading it alone), the others read the
// numbers and face corners of the next block's lines into records. Lines the records cannot hold (anything
// but a plain v, vn, vt or f line of at most PRE_CORNERS corners) are kept as runs, read when they are stored
// by obj_lines itself; so a record is at least 8 bytes of the file (a fast line) or a run, and the records of a
// block take at most 16 times its size.

/// Bytes of a block; corners a face record holds.
enum { OBJ_PARALLEL_BLOCK = 1 << 20, PRE_CORNERS = 4 };
/// Files from this size up are read on several threads.
#define OBJ_PARALLEL_MIN ((size_t)4 << 20)

/// Threads that read one file, at most (the render's limit).
enum { OBJ_MAX_THREADS = 256 };

/// One line as the fast paths read it, before anything is stored; or a run of lines they do not take.
typedef struct pre_line {
    const char *start; ///< the line, or the run's first line
    uint32_t length;   ///< FAST_OTHER: the run's bytes, whole lines
    uint8_t kind;      ///< fast_kind; FAST_OTHER: a run, read when it is stored
    uint8_t count;     ///< numbers, or corners
    union {
        float v[7];
        int32_t raw[PRE_CORNERS][3]; ///< fast_corner_raw's indices (a line with one beyond int32 is in a run)
    } u;
} pre_line;
_Static_assert(sizeof(pre_line) <= 64, "records of a block stay within 16 times its bytes");
_Static_assert(OBJ_MAX_LINE_BYTES < UINT32_MAX / 2, "a run's length holds any line");

/// The records of one part of a block, in line order.
typedef struct pre_part {
    pre_line *lines;
    size_t count, cap;
    bool nomem;
} pre_part;

/// A block of complete lines, text[0, upto), and the start of the next line after it, text[upto, have).
typedef struct obj_block {
    char *text;
    size_t cap, have, upto;
    bool eof;
    pre_part *parts; ///< the block's parts (obj_read_parallel's `parts` of them), split at line ends
} obj_block;

// Whether a corner's raw indices fit a record (an index beyond int32 is out of range for any mesh).
static inline bool fits_int32(const int64_t raw[3]) {
    return raw[0] >= INT32_MIN && raw[0] <= INT32_MAX && raw[1] >= INT32_MIN && raw[1] <= INT32_MAX &&
           raw[2] >= INT32_MIN && raw[2] <= INT32_MAX;
}

// What the fast paths would read of the line at s, into *pl (kind FAST_OTHER: none of it), storing nothing;
// returns the next line's start.
static const char *pre_scan_line(const char *s, const char *end, pre_line *pl) {
    pl->start = s;
    pl->kind = FAST_OTHER;
    fast_kind kind = fast_kind_of(s, end);
    const char *stop = NULL;
    bool ok = false;
    if (kind == FAST_FACE) {
        const char *p = s + 2;
        size_t n = 0;
        for (ok = true;;) {
            while (p < end && obj_is_space(*p)) p++;
            if (p == end || *p == '\n') break;
            int64_t raw[3];
            if (n == PRE_CORNERS || !(p = fast_corner_raw(p, end, raw)) || !fits_int32(raw)) {
                ok = false;
                break;
            }
            for (int k = 0; k < 3; k++) pl->u.raw[n][k] = (int32_t)raw[k];
            n++;
        }
        stop = p;
        ok = ok && n >= 3;
        pl->count = (uint8_t)n;
    } else if (kind != FAST_OTHER) {
        int count = 0;
        ok = fast_line_numbers(kind, s, end, pl->u.v, &count, &stop);
        pl->count = (uint8_t)count;
    }
    if (ok && (size_t)(stop - s) <= OBJ_MAX_LINE_BYTES) {
        pl->kind = (uint8_t)kind;
        return stop < end ? stop + 1 : end;
    }
    const char *nl = memchr(s, '\n', (size_t)(end - s));
    return nl ? nl + 1 : end;
}

// The line (or run) of record pl stored as obj_lines stores it. False on a failure (message set).
static bool pre_store(obj_parser *ps, const pre_line *pl, const char *end) {
    if (pl->kind == FAST_OTHER) return obj_lines(ps, pl->start, pl->length);
    ps->rep.line++;
    if (pl->kind == FAST_FACE) {
        if (ps->corner_cap < PRE_CORNERS &&
            !array_reserve((void **)&ps->corners, &ps->corner_cap, PRE_CORNERS, sizeof *ps->corners))
            return obj_out_of_memory(&ps->rep);
        bool ok = true;
        for (size_t k = 0; ok && k < pl->count; k++) {
            const int32_t *r = pl->u.raw[k];
            ok = fast_corner_resolve(&ps->model->mesh, (const int64_t[3]){r[0], r[1], r[2]}, &ps->corners[k]);
        }
        if (ok) return fast_store(ps, FAST_FACE, NULL, 0, pl->count) == FAST_OK;
    } else {
        return fast_store(ps, (fast_kind)pl->kind, pl->u.v, pl->count, 0) == FAST_OK;
    }
    // A corner out of range: the line as obj_lines reads it (which gives the message).
    const char *next;
    fast_result r = fast_line(ps, pl->start, end, &next);
    return r == FAST_OK ||
           (r == FAST_NO && add_queued(ps) && obj_read_line(pl->start, end, &ps->rep, statement_line, ps, &next));
}

/// One round of the parallel reader: store block `store` (NULL: none) while the parts of block `scan` (NULL:
/// none) are read. Item 0 stores, item k > 0 reads part k - 1.
typedef struct pre_round {
    obj_parser *ps;
    const obj_block *store;
    obj_block *scan;
    size_t parts;
    bool ok;
} pre_round;

// The first line of text[0, n) that starts at or after `at` (text + n when none does).
static const char *line_start_from(const char *text, size_t n, size_t at) {
    if (at == 0 || at >= n) return text + (at < n ? at : n);
    const char *nl = memchr(text + at - 1, '\n', n - (at - 1));
    return nl ? nl + 1 : text + n;
}

static void pre_round_run(void *ctx, size_t item) {
    pre_round *rd = ctx;
    if (item == 0) {
        const obj_block *b = rd->store;
        const char *end = b ? b->text + b->upto : NULL;
        for (size_t k = 0; b && rd->ok && k < rd->parts; k++)
            for (size_t i = 0; rd->ok && i < b->parts[k].count; i++) rd->ok = pre_store(rd->ps, &b->parts[k].lines[i], end);
        if (b && rd->ok) rd->ok = add_queued(rd->ps); // as obj_lines ends a block
        return;
    }
    obj_block *b = rd->scan;
    if (!b) return;
    size_t k = item - 1, n = b->upto;
    // Part k: from the first line that starts at or after k n / parts to the first at or after (k + 1) n / parts.
    const char *text = b->text, *end = text + n;
    size_t at = (size_t)((uint64_t)n * k / rd->parts), to = (size_t)((uint64_t)n * (k + 1) / rd->parts);
    const char *s = line_start_from(text, n, at), *e = line_start_from(text, n, to);
    pre_part *part = &b->parts[k];
    part->count = 0;
    while (s < e) {
        if (part->count == part->cap &&
            !array_reserve((void **)&part->lines, &part->cap, part->count + 1, sizeof *part->lines)) {
            part->nomem = true;
            return;
        }
        pre_line *pl = &part->lines[part->count];
        const char *next = pre_scan_line(s, end, pl);
        size_t bytes = (size_t)(next - s);
        pre_line *last = part->count ? pl - 1 : NULL;
        if (pl->kind != FAST_OTHER) {
            part->count++;
        } else if (last && last->kind == FAST_OTHER && last->length <= UINT32_MAX - bytes) {
            last->length += (uint32_t)bytes; // the line joins the run before it
        } else {
            pl->length = (uint32_t)bytes; // a line is shorter than a block's buffer (OBJ_MAX_LINE_BYTES + 1)
            part->count++;
        }
        s = next;
    }
}

// Fills block b: the unfinished line that `prev` ended with, then up to `block` bytes more of the file, cut at the
// last line end (all of it at the end of the file); more only while the unfinished line alone fills it. False on a
// read failure (*errnum set) or a line longer than the limit (*errnum 0, b->eof false, b->have its bytes so far).
static bool fill_block(FILE *f, obj_block *b, const obj_block *prev, size_t block, size_t *total, int *errnum) {
    size_t carried = prev ? prev->have - prev->upto : 0; // at most OBJ_MAX_LINE_BYTES: prev had a line end
    if (carried + block > b->cap && b->cap <= OBJ_MAX_LINE_BYTES) {
        // Room for the unfinished line and a block after it, within the most a line's buffer may take.
        size_t want = carried + block < OBJ_MAX_LINE_BYTES + 1 ? carried + block : OBJ_MAX_LINE_BYTES + 1;
        char *grown = realloc(b->text, want);
        if (!grown) {
            *errnum = ENOMEM;
            return false;
        }
        b->text = grown;
        b->cap = want;
    }
    b->have = carried;
    if (carried) memmove(b->text, prev->text + prev->upto, carried);
    b->upto = 0;
    for (;;) {
        if (b->have == b->cap && !grow_line_buffer(&b->text, &b->cap, errnum)) return false; // one unfinished line
        size_t room = b->cap - b->have, want = room < block ? room : block;
        size_t got = fread(b->text + b->have, 1, want, f);
        b->eof = got < want;
        if (b->eof && ferror(f)) *errnum = errno ? errno : EIO;
        else if ((*total += got) > OBJ_MAX_FILE_BYTES) *errnum = EFBIG;
        if (*errnum) return false;
        size_t before = b->have; // the bytes before hold no line end (the unfinished line)
        b->have += got;
        size_t upto = b->have;
        while (!b->eof && upto > before && b->text[upto - 1] != '\n') upto--;
        if (upto > before || b->eof) {
            b->upto = upto;
            return true;
        }
    }
}

// obj_read_stream on the pool's threads (see above): the same mesh, warnings and errors.
static bool obj_read_parallel(obj_parser *ps, FILE *f, thread_pool *pool, size_t block, int *errnum) {
    *errnum = 0;
    size_t parts = 2 * (size_t)thread_pool_size(pool), total = 0;
    obj_block blocks[2] = {{0}, {0}};
    bool ok = true;
    for (int i = 0; ok && i < 2; i++) {
        blocks[i].text = malloc(block);
        blocks[i].cap = block;
        blocks[i].parts = calloc(parts, sizeof *blocks[i].parts);
        ok = blocks[i].text && blocks[i].parts;
    }
    obj_block *cur = &blocks[0], *spare = &blocks[1], *pending = NULL; // pending: read, not stored yet
    bool filled = false;
    if (!ok) *errnum = ENOMEM;
    else filled = fill_block(f, cur, NULL, block, &total, errnum);
    while (filled) {
        pre_round rd = {ps, pending, cur, parts, true};
        thread_pool_run(pool, parts + 1, pre_round_run, &rd);
        pending = NULL;
        if (!rd.ok) { // a line failed: its message is set
            ok = false;
            break;
        }
        bool nomem = false;
        for (size_t k = 0; k < parts; k++) nomem = nomem || cur->parts[k].nomem;
        if (nomem) {
            ok = obj_out_of_memory(&ps->rep);
            break;
        }
        pending = cur;
        if (cur->eof) break;
        filled = fill_block(f, spare, cur, block, &total, errnum);
        obj_block *t = cur;
        cur = spare;
        spare = t;
    }
    if (ok && pending) {
        pre_round rd = {ps, pending, NULL, parts, true};
        pre_round_run(&rd, 0);
        ok = rd.ok;
        if (!ok) *errnum = 0; // a line before the read failure failed first
    }
    if (ok && !filled && !*errnum) ok = line_too_long_read_on(ps, f, cur->text, cur->cap, cur->have);
    if (*errnum) ok = false;
    for (int i = 0; i < 2; i++) {
        for (size_t k = 0; blocks[i].parts && k < parts; k++) free(blocks[i].parts[k].lines);
        free(blocks[i].parts);
        free(blocks[i].text);
    }
    return ok;
}

bool obj_read_open_file(obj_parser *ps, FILE *f, size_t size, int *errnum) {
    const obj_options *opt = ps->opt;
    // A large file on several threads (fast paths only: statements_only reads every line as a statement).
    int threads = opt && opt->threads ? opt->threads : 1;
    if (threads < 0) threads = thread_pool_online_cpus();
    if (threads > OBJ_MAX_THREADS) threads = OBJ_MAX_THREADS;
    size_t min = opt && opt->parallel_min ? opt->parallel_min : OBJ_PARALLEL_MIN;
    size_t block = opt && opt->parallel_min ? (opt->parallel_min > 16 ? opt->parallel_min : 16) : OBJ_PARALLEL_BLOCK;
    thread_pool *pool = threads > 1 && size >= min && !opt->statements_only ? thread_pool_start(threads) : NULL;
    bool ok = pool && thread_pool_size(pool) > 1 ? obj_read_parallel(ps, f, pool, block, errnum)
                                                 : obj_read_stream(ps, f, errnum);
    thread_pool_stop(pool);
    return ok;
}
