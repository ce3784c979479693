// mtl.h — the Wavefront MTL reader: a material library read into plain records, one per `newmtl`, holding what
// the file says and nothing more. Turning a record into a glint material is the scene's policy
// (scene/scene_file_mesh.c), not the reader's.
//
// Read into the record: `newmtl name`, `Kd`, `Ks`, `Ke`, `Tf` (r [g b], g = b = r when one number is given;
// components >= 0), `Ns`, `Ni` (>= 0), `d` (optionally `-halo`) and `Tr` (in [0, 1]), `illum` (an integer from 0
// to 10), `map_Kd [-options] file` (the options skipped; the file resolved relative to the MTL file, `\` turned
// into `/`, a Windows absolute path retried as its file name next to the MTL file).
// Read (`Ka` checked as a colour) and not used: `Ka`, the other keys mtl_unsupported_key_name names, and the
// options `map_Kd -o ...` and `d -halo`; the library records which of them the file gives
// (mtl_library.unsupported) and the line of the first, so that its user can name them once per file.
// `Kd spectral`, `Kd xyz` (and the same of the other colours) and unknown statements are warnings of the
// reader, once per keyword and file.
//
// Errors ("file:line: what is wrong, expected what"): a key other than `newmtl` before the first `newmtl`, a
// `newmtl` or `map_Kd` without a name, malformed or non-finite numbers, too few or too many numbers, values out
// of range. Warnings: a name defined again (the first definition is kept), a texture that cannot be found
// (map_kd NULL), unsupported statements. Lines are limited to OBJ_MAX_LINE_BYTES (obj_text.h); the OBJ reader
// reads MTL files of up to MTL_MAX_FILE_BYTES.
#ifndef GLINT_MTL_H
#define GLINT_MTL_H

#include "core/status.h"
#include "core/vec.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// Largest MTL file read, in bytes (64 MiB): material libraries are small.
#define MTL_MAX_FILE_BYTES ((size_t)64 << 20)
/// How many keys mtl_unsupported_key_name names (bits of mtl_library.unsupported).
#define MTL_UNSUPPORTED_KEYS 29

/// The values of one `newmtl` block that glint reads, as the file gives them (has_*: given).
typedef struct mtl_values {
    bool has_kd, has_ks, has_ke, has_tf, has_ns, has_ni, has_d, has_tr;
    vec3 kd, ks, ke, tf; ///< colours: diffuse, specular, emitted, transmission filter (components >= 0)
    float ns, ni, d, tr; ///< specular exponent (>= 0), index of refraction (>= 0), dissolve and its inverse Tr ([0, 1])
    int illum;           ///< the illumination model, 0..10; -1 when absent
} mtl_values;

/// One material of a library.
typedef struct mtl_record {
    char *name;        ///< the `newmtl` name
    long line;         ///< the line of its `newmtl`
    char *map_kd;      ///< map_Kd as a path usable from the current directory; NULL when absent or not found
    mtl_values values; ///< what the block says
} mtl_record;

/// Everything one MTL file defines.
typedef struct mtl_library {
    mtl_record *records;   ///< in file order; a name defined again keeps its first definition
    size_t count;
    uint32_t unsupported;  ///< bit k set: the file gives key mtl_unsupported_key_name(k) (in any block)
    long unsupported_line; ///< the line of the first unsupported key; 0 when there is none
    size_t warning_count;  ///< warnings reported (including those not passed to a callback)
} mtl_library;

/// Receives each warning, formatted "file:line: warning: what happened; what is done instead".
typedef void (*mtl_warning_fn)(const char *message, void *user);

/// Options of mtl_parse; NULL or a zeroed struct: no callback, texture files checked.
typedef struct mtl_options {
    mtl_warning_fn warn; ///< NULL: warnings are only counted
    void *user;          ///< passed to warn
    bool skip_files;     ///< do not check that texture files exist (fuzzing, in-memory use)
} mtl_options;

/// Parses an MTL library from memory into *out; texture paths are resolved relative to the directory of `name`.
/// On failure returns GLINT_ERR_INPUT (GLINT_ERR_RENDER when memory runs out), a message in *err and an empty
/// *out. Free with mtl_library_free().
glint_status mtl_parse(const char *name, const char *text, size_t length, const mtl_options *opt, mtl_library *out,
                       glint_error *err);
/// Frees the records of a library and leaves it empty.
void mtl_library_free(mtl_library *lib);
/// What bit k of mtl_library.unsupported stands for: a key as files write it ("Ka", "map_Bump"), or an option of
/// a used key ("map_Kd -options", "d -halo"); NULL past the last.
const char *mtl_unsupported_key_name(unsigned k);

#endif
