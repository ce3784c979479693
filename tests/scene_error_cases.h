// scene_error_cases.h — the table of malformed scenes and the exact message each must give: read as files by
// test_scene_errors.c, and rebuilt call by call through the scene API by test_scene_api.c (the same messages
// after "glint_scene_add_...: " instead of "bad.json:line:col: ").
#ifndef GLINT_SCENE_ERROR_CASES_H
#define GLINT_SCENE_ERROR_CASES_H

#include <stddef.h>

/// One malformed scene: its text (len 0 = up to the NUL) and the whole message glint must print.
typedef struct bad_scene {
    int line; ///< where the case is in this file, for failure reports
    const char *text;
    size_t len;
    const char *message;
} bad_scene;

// For texts that contain a NUL byte.
#define BYTES(s) s, sizeof(s) - 1
#define TEXT(s) s, 0

static const bad_scene cases[] = {
    // --- JSON syntax ---
    {__LINE__, TEXT(""), "bad.json:1:1: the file is empty; expected a JSON object"},
    {__LINE__, TEXT(" \n\t\n"), "bad.json:1:1: the file holds only white space; expected a JSON object"},
    {__LINE__, TEXT("{\n  \"render\": {\"width\": 64,"),
     "bad.json:2:26: expected a key in double quotes, got end of file"},
    {__LINE__, TEXT("{\"render\": {\"output\": \"gam"), "bad.json:1:23: unterminated string; expected a closing '\"'"},
    {__LINE__, TEXT("{\"render\" {}}"), "bad.json:1:11: expected ':' after the key \"render\", got '{'"},
    {__LINE__, TEXT("{\"objects\": [1, 2,]}"),
     "bad.json:1:18: trailing comma before ']'; expected another value after ','"},
    {__LINE__, TEXT("{\"render\": {\"spp\": 4,}}"),
     "bad.json:1:21: trailing comma before '}'; expected another key after ','"},
    {__LINE__, TEXT("{\"render\": {\"width\": 0768}}"),
     "bad.json:1:22: invalid number '0768'; expected a JSON number such as 12, -0.5 or 6.02e23"},
    {__LINE__, TEXT("{\"render\": {\"width\": NaN}}"),
     "bad.json:1:22: expected a value (object, array, string, number, true, false or null), got 'NaN'"},
    {__LINE__, TEXT("{\"render\": {}} {\"camera\": {}}"),
     "bad.json:1:16: unexpected '{' after the end of the top-level value; expected end of file"},
    {__LINE__, TEXT("{\"render\": {}}\ngarbage"),
     "bad.json:2:1: unexpected 'garbage' after the end of the top-level value; expected end of file"},
    {__LINE__, TEXT("{'render': {}}"), "bad.json:1:2: expected a key in double quotes or '}', got '''"},
    {__LINE__, TEXT("{\n  // a comment\n  \"render\": {}\n}"),
     "bad.json:2:3: expected a key in double quotes or '}', got '/'"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\"} {\"type\": \"sphere\"}]}"),
     "bad.json:1:33: expected ',' or ']' after an element of the array opened at 1:13, got '{'"},
    {__LINE__, TEXT("{\"materials\": {\"a\": {\"type\": \"phong\"]}}"),
     "bad.json:1:37: expected ',' or '}' after a member of the object opened at 1:21, got ']'"},
    {__LINE__, TEXT("{\"materials\": {\"bad\tname\": {}}}"),
     "bad.json:1:20: control character U+0009 inside a string; write it as \\u0009"},
    {__LINE__, TEXT("{\"materials\": {\"a\nb\": {}}}"),
     "bad.json:1:18: line break inside a string; expected a closing '\"' first (write \\n for a line break)"},
    {__LINE__, TEXT("{\"render\": {\"output\": \"srgb\\x\"}}"),
     "bad.json:1:28: invalid escape '\\x' in a string; expected one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX"},
    {__LINE__, TEXT("{\"materials\": {\"\\ud83d\": {}}}"),
     "bad.json:1:17: unpaired UTF-16 high surrogate \\uD83D; expected a low surrogate \\uDC00-\\uDFFF after it"},
    {__LINE__, TEXT("{\"materials\": {\"a\\u0000b\": {}}}"), "bad.json:1:18: \\u0000 (NUL) is not allowed in a string"},
    {__LINE__, BYTES("{\"render\": {}}\0"),
     "bad.json:1:15: unexpected control character U+0000 after the end of the top-level value; expected end of file"},
    {__LINE__, BYTES("{\"materials\": {\"a\0\": {}}}"),
     "bad.json:1:18: NUL byte inside a string; strings cannot contain U+0000"},
    // Invisible characters are named by their code point (one byte-order mark at the start is allowed).
    {__LINE__, TEXT("\xEF\xBB\xBF\xEF\xBB\xBF{}"),
     "bad.json:1:1: expected a value (object, array, string, number, true, false or null), got byte-order mark U+FEFF"},
    {__LINE__, TEXT("{}\xEF\xBB\xBF"),
     "bad.json:1:3: unexpected byte-order mark U+FEFF after the end of the top-level value; expected end of file"},
    {__LINE__, TEXT("{\xE2\x80\x8B}"),
     "bad.json:1:2: expected a key in double quotes or '}', got invisible character U+200B"},
    {__LINE__, TEXT("{\"materials\": {\"caf\xe9\": {}}}"),
     "bad.json:1:20: invalid UTF-8 byte 0xE9 in a string; the file must be UTF-8"},
    {__LINE__, TEXT("{\"render\": {\"seed\": 1234567890123456789012345678901234567890123456789012345678901234567890}}"),
     "bad.json:1:21: number '123456789012345678901234...' has 70 characters; at most 63 are allowed"},
    // --- the shape of the scene ---
    {__LINE__, TEXT("[{\"type\": \"sphere\"}]"),
     "bad.json:1:1: the scene must be a JSON object, got [{\"type\": \"sphere\"}]"},
    {__LINE__, TEXT("{\"render\": {}, \"cameras\": {}}"),
     "bad.json:1:16: unknown key \"cameras\" in the scene; expected one of: render, camera, textures, materials, "
     "objects, lights"},
    {__LINE__, TEXT("{\"render\": {\"samples\": 4}}"),
     "bad.json:1:13: unknown key \"samples\" in render; expected one of: width, height, spp, max_depth, seed, "
     "sampler, noise_threshold, integrator, background, output, accel, presplit, spatial_splits"},
    {__LINE__, TEXT("{\"render\": {\"sampler\": \"halton\"}}"),
     "bad.json:1:24: \"sampler\" must be \"sobol\" or \"independent\", got \"halton\""},
    {__LINE__, TEXT("{\"render\": {\"noise_threshold\": -0.5}}"),
     "bad.json:1:32: \"noise_threshold\" must be a number in [0, 1000], got -0.5"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"viewport\", \"vfov\": 40}}"),
     "bad.json:1:33: unknown key \"vfov\" in camera (viewport); expected one of: type, position, viewport, distance, "
     "shutter"},
    {__LINE__, TEXT("{\"materials\": {\n  \"red\": {\"type\": \"phong\", \"colour\": [1, 0, 0]}\n}}"),
     "bad.json:2:28: unknown key \"colour\" in material \"red\"; expected one of: type, color, specular, reflective, "
     "specular_color"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"centre\": [0, 0, 0], \"radius\": 1, "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:33: unknown key \"centre\" in object 0 (sphere); expected one of: type, center, center2, radius, "
     "material, transform, transform2, importance"},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"ambient\", \"intensity\": 0.2, \"position\": [0, 0, 0]}]}"),
     "bad.json:1:51: unknown key \"position\" in light 0 (ambient); expected one of: type, intensity"},
    {__LINE__, TEXT("{\"render\": {\"width\": 64, \"width\": 32}}"),
     "bad.json:1:26: duplicate key \"width\" in render (first given at 1:13)"},
    {__LINE__, TEXT("{\"materials\": {\"red\": {\"type\": \"phong\"}, \"red\": {\"type\": \"phong\"}}}"),
     "bad.json:1:42: duplicate material name \"red\" (first defined at 1:16)"},
    {__LINE__, TEXT("{\"render\": [400, 225]}"), "bad.json:1:12: render must be a JSON object, got [400, 225]"},
    {__LINE__, TEXT("{\"materials\": [{\"type\": \"phong\"}]}"),
     "bad.json:1:15: \"materials\" must be a JSON object mapping names to materials, got [{\"type\": \"phong\"}]"},
    {__LINE__, TEXT("{\"objects\": {\"type\": \"sphere\"}}"),
     "bad.json:1:13: \"objects\" must be an array of objects, got an object"},
    {__LINE__, TEXT("{\"objects\": [\"sphere\"]}"), "bad.json:1:14: object 0 must be a JSON object, got \"sphere\""},
    {__LINE__, TEXT("{\"materials\": {\"\": {\"type\": \"phong\"}}}"),
     "bad.json:1:16: material name \"\" must be 1 to 128 bytes long"},
    // --- render settings ---
    {__LINE__, TEXT("{\"render\": {\"width\": \"768\"}}"),
     "bad.json:1:22: \"width\" must be an integer in [1, 16384], got \"768\""},
    {__LINE__, TEXT("{\"render\": {\"width\": 768.5}}"),
     "bad.json:1:22: \"width\" must be an integer in [1, 16384], got 768.5"},
    {__LINE__, TEXT("{\"render\": {\"width\": 1000000000}}"),
     "bad.json:1:22: \"width\" must be an integer in [1, 16384], got 1000000000"},
    {__LINE__, TEXT("{\"render\": {\"height\": -225}}"),
     "bad.json:1:23: \"height\" must be an integer in [1, 16384], got -225"},
    {__LINE__, TEXT("{\"render\": {\"spp\": 0}}"), "bad.json:1:20: \"spp\" must be an integer in [1, 1000000], got 0"},
    {__LINE__, TEXT("{\"render\": {\"max_depth\": -1}}"),
     "bad.json:1:26: \"max_depth\" must be an integer in [0, 10000], got -1"},
    {__LINE__, TEXT("{\"render\": {\"seed\": 9007199254740994}}"),
     "bad.json:1:21: \"seed\" must be an integer in [0, 9007199254740992], got 9007199254740994"},
    // The double rounds 2^53 + 1 to 2^53: the text itself must be in range, as the command line's --seed checks.
    {__LINE__, TEXT("{\"render\": {\"seed\": 9007199254740993}}"),
     "bad.json:1:21: \"seed\" must be an integer in [0, 9007199254740992], got 9007199254740993"},
    {__LINE__, TEXT("{\"render\": {\"width\": 64.00000000000000001}}"),
     "bad.json:1:22: \"width\" must be an integer in [1, 16384], got 64.00000000000000001"},
    {__LINE__, TEXT("{\"render\": {\"spp\": null}}"),
     "bad.json:1:20: \"spp\" must be an integer in [1, 1000000], got null"},
    {__LINE__, TEXT("{\"render\": {\"output\": \"gamma\"}}"),
     "bad.json:1:23: \"output\" must be \"linear\", \"gamma2\" or \"srgb\", got \"gamma\""},
    {__LINE__, TEXT("{\"render\": {\"accel\": \"kdtree\"}}"),
     "bad.json:1:22: \"accel\" must be \"bvh\", \"bvh2\" or \"none\", got \"kdtree\""},
    {__LINE__, TEXT("{\"render\": {\"integrator\": \"raytrace\"}}"),
     "bad.json:1:27: \"integrator\" must be \"whitted\", \"path\" or an object with a \"type\", got \"raytrace\""},
    {__LINE__, TEXT("{\"render\": {\"integrator\": {\"type\": \"whitted\", \"mode\": \"colour\"}}}"),
     "bad.json:1:55: \"mode\" must be \"paper\" or \"color\", got \"colour\""},
    {__LINE__, TEXT("{\"render\": {\"integrator\": {\"type\": \"path\", \"mode\": \"paper\"}}}"),
     "bad.json:1:44: unknown key \"mode\" in integrator (path); expected one of: type"},
    {__LINE__, TEXT("{\"render\": {\"background\": \"blue\"}}"),
     "bad.json:1:27: \"background\" must be a colour (a number or [r, g, b]), "
     "\"sky\" or an object with a \"type\", got "
     "\"blue\""},
    {__LINE__, TEXT("{\"render\": {\"background\": [1, 1]}}"),
     "bad.json:1:27: \"background\" must be a finite number >= 0 or an array of 3 such numbers [r, g, b], got [1, 1]"},
    {__LINE__, TEXT("{\"render\": {\"background\": {\"type\": \"sky\", \"zenith\": [0.5, -0.7, 1]}}}"),
     "bad.json:1:59: \"zenith\"[1] must be a finite number >= 0, got -0.7"},
    // --- camera ---
    {__LINE__, TEXT("{\"camera\": {\"type\": \"pinhole\"}}"),
     "bad.json:1:21: \"type\" must be \"viewport\", \"lookat\" or \"import\", got \"pinhole\""},
    {__LINE__, TEXT("{\"camera\": {\"lookfrom\": [0, 0, 1]}}"),
     "bad.json:1:12: missing required key \"type\" in camera; expected one of \"viewport\", \"lookat\" or \"import\""},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"lookfrom\": [1, 2, 3], \"lookat\": [1, 2, 3]}}"),
     "bad.json:1:64: \"lookfrom\" and \"lookat\" must be different points"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 5, 0], \"lookat\": [0, 0, 0]}}"),
     "bad.json:1:12: \"vup\" must be a non-zero vector not parallel to the view direction (lookat - lookfrom)"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"vfov\": 180}}"),
     "bad.json:1:39: \"vfov\" must be a number in (0, 180), got 180"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"focus_distance\": -10}}"),
     "bad.json:1:49: \"focus_distance\" must be a finite number >= 0, got -10"},
    // What would render as NaN: a view, a shape or a light beyond the extent where squared distances overflow.
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"focus_distance\": 1e38}}"),
     "bad.json:1:49: the camera's view reaches -inf on the x axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"vfov\": 179.9999}}"),
     "bad.json:1:39: the camera's view reaches 1.59196e+10 on the x axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"viewport\", \"position\": [3e38, 3e38, 3e38]}}"),
     "bad.json:1:45: the camera's view reaches 3e+38 on the x axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 2e9, 0], \"radius\": 1, \"material\": \"m\"}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:43: the sphere reaches 2e+09 on the y axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\", \"transform\": [{\"scale\": [1e30, 1, 1]}]}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:97: the transformed sphere reaches 1e+30 on the x axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 0, 2e9], \"material\": \"m\"}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:36: the shape reaches 2e+09 on the z axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"point\", \"intensity\": 1, \"position\": [0, 0, -5e9]}]}"),
     "bad.json:1:59: the light reaches -5e+09 on the z axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"viewport\", \"viewport\": [1, 0]}}"),
     "bad.json:1:49: \"viewport\"[1] must be a finite number > 0, got 0"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"viewport\", \"distance\": 0}}"),
     "bad.json:1:45: \"distance\" must be a finite number > 0, got 0"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"viewport\", \"position\": [0, 0]}}"),
     "bad.json:1:45: \"position\" must be an array of 3 numbers (x, y, z), got [0, 0]"},
    // --- materials ---
    {__LINE__, TEXT("{\"materials\": {\"glass\": {\"type\": \"glass\", \"ior\": 1.5}}}"),
     "bad.json:1:34: \"type\" must be \"lambertian\", \"metal\", \"dielectric\", "
     "\"phong\", \"diffuse_light\", \"conductor\", \"rough_dielectric\" or \"pbr\", got \"glass\""},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"albedo\": [1, 1, 1]}}}"),
     "bad.json:1:21: missing required key \"type\" in material \"m\"; expected one of \"lambertian\", \"metal\", "
     "\"dielectric\", \"phong\", \"diffuse_light\", \"conductor\", \"rough_dielectric\" or \"pbr\""},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"conductor\", \"metal\": \"Zn\"}}}"),
     "bad.json:1:52: \"metal\" must be one of \"Ag\", \"Al\", \"Au\", \"Cr\", \"Cu\", \"Fe\", \"Pb\", \"Pt\", got \"Zn\""},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"conductor\", \"metal\": \"Au\", \"f0\": 1}}}"),
     "bad.json:1:21: a conductor takes one of \"metal\", \"eta\" with \"k\", or \"f0\", not several"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"conductor\", \"k\": [3, 2, 1]}}}"),
     "bad.json:1:48: a conductor's \"eta\" and \"k\" come together: \"eta\" is missing"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"conductor\", \"anisotropy\": 1}}}"),
     "bad.json:1:57: \"anisotropy\" must be a number in [0, 1), got 1"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"rough_dielectric\", \"roughness\": 2}}}"),
     "bad.json:1:63: \"roughness\" must be a number in [0, 1], got 2"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"pbr\", \"metallic\": [1]}}}"),
     "bad.json:1:49: \"metallic\" must be a number in [0, 1], a texture name or a texture object (its blue channel), "
     "got [1]"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"pbr\", \"roughness\": \"none\"}}}"),
     "bad.json:1:50: texture \"none\" is not defined (no named textures are defined)"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"pbr\", \"normal_map\": 1}}}"),
     "bad.json:1:51: \"normal_map\" must be a texture name or a texture object, got 1"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"pbr\", \"alpha\": 0.5}}}"),
     "bad.json:1:46: \"alpha\" needs \"alpha_cutoff\": glint cuts surfaces where alpha < alpha_cutoff (an alpha mask) "
     "and does not blend"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"pbr\", \"alpha\": true, \"alpha_cutoff\": 0.5}}}"),
     "bad.json:1:46: \"alpha\" must be a number in [0, 1], a texture name or a texture object (its alpha channel), got true"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"pbr\", \"alpha_cutoff\": 2}}}"),
     "bad.json:1:53: \"alpha_cutoff\" must be a number in [0, 1], got 2"},
    {__LINE__, TEXT("{\"materials\": {\"steel\": {\"type\": \"metal\", \"fuzz\": 2}}}"),
     "bad.json:1:51: \"fuzz\" must be a number in [0, 1], got 2"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": [0.5, 1.5, 0.5]}}}"),
     "bad.json:1:60: \"albedo\"[1] must be a number in [0, 1], got 1.5"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": \"red\"}}}"),
     "bad.json:1:54: texture \"red\" is not defined (no named textures are defined)"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": true}}}"),
     "bad.json:1:54: \"albedo\" must be a number in [0, 1], an array of 3 such numbers [r, g, b], a texture name or a "
     "texture object, got true"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": [1, 1]}}}"),
     "bad.json:1:54: \"albedo\" must be a number in [0, 1], an array of 3 such numbers [r, g, b], a texture name or a "
     "texture object, got [1, 1]"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"phong\", \"specular_color\": \"t\"}}}"),
     "bad.json:1:57: \"specular_color\" must be a number in [0, 1] or an array of 3 such numbers [r, g, b], got \"t\""},
    {__LINE__, TEXT("{\"materials\": {\"g\": {\"type\": \"dielectric\", \"ior\": 0}}}"),
     "bad.json:1:51: \"ior\" must be a finite number > 0, got 0"},
    {__LINE__, TEXT("{\"materials\": {\"r\": {\"type\": \"phong\", \"specular\": 9900.5}}}"),
     "bad.json:1:51: \"specular\" must be an integer in [-1, 2147483647], got 9900.5"},
    {__LINE__, TEXT("{\"materials\": {\"r\": {\"type\": \"phong\", \"reflective\": -0.2}}}"),
     "bad.json:1:53: \"reflective\" must be a number in [0, 1], got -0.2"},
    {__LINE__, TEXT("{\"render\": {\"presplit\": 1}}"), "bad.json:1:25: \"presplit\" must be true or false, got 1"},
    {__LINE__, TEXT("{\"render\": {\"spatial_splits\": \"no\"}}"),
     "bad.json:1:31: \"spatial_splits\" must be true or false, got \"no\""},
    {__LINE__, TEXT("{\"materials\": {\"l\": {\"type\": \"diffuse_light\", \"two_sided\": \"yes\"}}}"),
     "bad.json:1:60: \"two_sided\" must be true or false, got \"yes\""},
    {__LINE__, TEXT("{\"materials\": {\"l\": {\"type\": \"diffuse_light\", \"emission\": 1e999}}}"),
     "bad.json:1:59: \"emission\" must be a finite number >= 0 or an array of 3 such numbers [r, g, b], got 1e999"},
    // --- objects ---
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"cube\", \"size\": 1}]}"),
     "bad.json:1:23: \"type\" must be \"sphere\", \"quad\", \"box\", \"mesh\", \"constant_medium\", "
     "\"homogeneous_medium\" or \"import\", got \"cube\""},
    {__LINE__, TEXT("{\"objects\": [\n  {\"type\": \"sphere\", \"radius\": 1, \"material\": \"m\"}\n]}"),
     "bad.json:2:3: missing required key \"center\" in object 0 (sphere)"},
    {__LINE__, TEXT("{\"objects\": [{\"center\": [0, 0, 0]}]}"),
     "bad.json:1:14: missing required key \"type\" in object 0; expected one of \"sphere\", \"quad\", \"box\", "
     "\"mesh\", \"constant_medium\", \"homogeneous_medium\" or \"import\""},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0, "
                    "\"material\": {\"type\": \"phong\"}}]}"),
     "bad.json:1:64: \"radius\" must be a finite non-zero number, got 0"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": \"abc\", "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:64: \"radius\" must be a finite non-zero number, got \"abc\""},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1e999, "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:64: \"radius\" must be a finite non-zero number, got 1e999"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1e39, "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:64: \"radius\" must be a finite non-zero number, got 1e39"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, -1e999, 0], \"radius\": 1, "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:47: \"center\"[1] must be a finite number, got -1e999"},
    {__LINE__,
     TEXT("{\"materials\": {\"red\": {\"type\": \"phong\"}, \"green\": {\"type\": \"phong\"}},\n"
          " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"blu\"}]}"),
     "bad.json:2:79: material \"blu\" is not defined (defined: red, green)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
                    "\"material\": \"red\"}]}"),
     "bad.json:1:79: material \"red\" is not defined (no named materials are defined)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": 3}]}"),
     "bad.json:1:79: \"material\" must be the name of a material in \"materials\" or a material object, got 3"},
    {__LINE__,
     TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
          "\"material\": {\"type\": \"metal\", "
          "\"roughness\": 1}}]}"),
     "bad.json:1:97: unknown key \"roughness\" in the material of object 0 (sphere); expected one of: type, "
     "albedo, fuzz"},
    // --- textures ---
    {__LINE__, TEXT("{\"textures\": [{\"type\": \"solid\"}]}"),
     "bad.json:1:14: \"textures\" must be a JSON object mapping names to textures, got [{\"type\": \"solid\"}]"},
    {__LINE__, TEXT("{\"textures\": {\"wood\": {\"type\": \"wood\"}}}"),
     "bad.json:1:32: \"type\" must be \"solid\", \"checker\", \"noise\", \"turbulence\", \"marble\" or \"image\", "
     "got \"wood\""},
    {__LINE__, TEXT("{\"textures\": {\"c\": {\"type\": \"checker\", \"size\": 2}}}"),
     "bad.json:1:40: unknown key \"size\" in texture \"c\"; expected one of: type, scale, even, odd"},
    {__LINE__, TEXT("{\"textures\": {\"c\": {\"type\": \"checker\", \"scale\": 0}}}"),
     "bad.json:1:49: \"scale\" must be a finite number > 0, got 0"},
    {__LINE__, TEXT("{\"textures\": {\"c\": {\"type\": \"checker\", \"scale\": 1e-40}}}"),
     "bad.json:1:49: \"scale\" must be at least 1.17549e-38, got 1e-40"},
    {__LINE__, TEXT("{\"textures\": {\"c\": {\"type\": \"checker\", \"odd\": [0, -1, 0]}}}"),
     "bad.json:1:51: \"odd\"[1] must be a finite number >= 0, got -1"},
    {__LINE__, TEXT("{\"textures\": {\"n\": {\"type\": \"noise\", \"depth\": 7}}}"),
     "bad.json:1:38: unknown key \"depth\" in texture \"n\"; expected one of: type, scale, color, seed, perlin"},
    {__LINE__, TEXT("{\"textures\": {\"m\": {\"type\": \"marble\", \"depth\": 0}}}"),
     "bad.json:1:48: \"depth\" must be an integer in [1, 32], got 0"},
    {__LINE__, TEXT("{\"textures\": {\"s\": {\"type\": \"solid\"}}}"),
     "bad.json:1:20: missing required key \"color\" in texture \"s\""},
    {__LINE__, TEXT("{\"textures\": {\"i\": {\"type\": \"image\", \"file\": \"\"}}}"),
     "bad.json:1:46: \"file\" must be a non-empty string (a path relative to the scene file), got \"\""},
    {__LINE__, TEXT("{\"textures\": {\"a\": {\"type\": \"solid\", \"color\": 1}, "
                    "\"a\": {\"type\": \"solid\", \"color\": 0}}}"),
     "bad.json:1:51: duplicate texture name \"a\" (first defined at 1:15)"},
    {__LINE__,
     TEXT("{\"textures\": {\"wood\": {\"type\": \"solid\", \"color\": 0.5}, \"tiles\": {\"type\": \"checker\"}},\n"
          " \"materials\": {\"m\": {\"type\": \"metal\", \"albedo\": \"woood\"}}}"),
     "bad.json:2:49: texture \"woood\" is not defined (defined: wood, tiles)"},
    {__LINE__,
     TEXT("{\"textures\": {\"hot\": {\"type\": \"solid\", \"color\": [1, 2, 1]}},\n"
          " \"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": \"hot\"}}}"),
     "bad.json:2:54: \"albedo\" must stay in [0, 1], but this texture has colour components up to 2"},
    {__LINE__,
     TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": {\"type\": \"checker\", \"even\": 0.5, "
          "\"odd\": 3}}}}"),
     "bad.json:1:54: \"albedo\" must stay in [0, 1], but this texture has colour components up to 3"},
    {__LINE__,
     TEXT("{\"materials\": {\"m\": {\"type\": \"dielectric\", \"tint\": {\"type\": \"noise\", \"scael\": 4}}}}"),
     "bad.json:1:70: unknown key \"scael\" in the texture \"tint\" of material \"m\"; expected one of: type, scale, "
     "color, seed, perlin"},
    {__LINE__, TEXT("{\"textures\": {\"i\": {\"type\": \"image\", \"file\": \"x.png\", \"encoding\": \"gamma\"}}}"),
     "bad.json:1:67: \"encoding\" must be \"srgb\" or \"linear\", got \"gamma\""},
    {__LINE__, TEXT("{\"textures\": {\"n\": {\"type\": \"noise\", \"perlin\": {\"gradients\": [[1, 0, 0]]}}}}"),
     "bad.json:1:62: \"gradients\" must be an array of 256 vectors [x, y, z], got [[1, 0, 0]]"},
    {__LINE__, TEXT("{\"textures\": {\"n\": {\"type\": \"noise\", \"perlin\": {\"perm_x\": []}}}}"),
     "bad.json:1:48: missing required key \"gradients\" in perlin"},
    {__LINE__, TEXT("{\"materials\": {\"l\": {\"type\": \"diffuse_light\", \"emission\": {\"color\": 4}}}}"),
     "bad.json:1:59: missing required key \"type\" in the texture \"emission\" of material \"l\"; expected one of "
     "\"solid\", \"checker\", \"noise\", \"turbulence\", \"marble\" or \"image\""},
    // --- transforms ---
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\", "
                    "\"transform\": [{\"translate\": [1, 0, 0]}, 3]}]}"),
     "bad.json:2:124: transform[1] must be a JSON object, got 3"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], "
                    "\"material\": \"m\", \"transform\": {\"translate\": [1, 0, 0]}}]}"),
     "bad.json:2:109: \"transform\" must be an array of operations ({\"translate\": ...}, {\"rotate\": ...}, "
     "{\"scale\": ...} or {\"matrix\": ...}), got an object"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"rotation\": {\"axis\": [0, 1, 0], \"degrees\": 15}}]}]}"),
     "bad.json:3:19: unknown key \"rotation\" in transform[0]; expected one of: translate, rotate, scale, matrix"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"scale\": 2}, {\"translate\": [1, 0, 0], \"scale\": 2}]}]}"),
     "bad.json:3:32: transform[1] must hold exactly one operation (translate, rotate, scale or matrix), got 2; put "
     "each in its own element, they apply in array order"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{}]}]}"),
     "bad.json:3:18: transform[0] must hold exactly one operation (translate, rotate, scale or matrix), got 0; put "
     "each in its own element, they apply in array order"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"rotate\": {\"axis\": [0, 0, 0], \"degrees\": 15}}]}]}"),
     "bad.json:3:38: \"axis\" must be a non-zero vector, got [0, 0, 0]"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"rotate\": {\"axis\": [0, 1, 0], \"angle\": 15}}]}]}"),
     "bad.json:3:49: unknown key \"angle\" in \"rotate\" of transform[0]; expected one of: axis, degrees"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"rotate\": {\"axis\": [0, 1, 0]}}]}]}"),
     "bad.json:3:29: missing required key \"degrees\" in \"rotate\" of transform[0]"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"scale\": 0}]}]}"),
     "bad.json:3:28: \"scale\" must be a finite non-zero number, got 0"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"scale\": [1, 0, 1]}]}]}"),
     "bad.json:3:32: \"scale\"[1] must be a finite non-zero number, got 0"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"scale\": \"2\"}]}]}"),
     "bad.json:3:28: \"scale\" must be a finite non-zero number or an array of 3 such numbers [x, y, z], got \"2\""},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"matrix\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]}]}]}"),
     "bad.json:3:29: \"matrix\" is singular (determinant 0); expected an invertible matrix"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"matrix\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1]}]}]}"),
     "bad.json:3:29: \"matrix\" must be affine: its last row must be [0, 0, 0, 1], got [0, 0, 1, 1]"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"matrix\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]}]}]}"),
     "bad.json:3:29: \"matrix\" must be an array of 16 numbers (a 4x4 matrix, row by row), got [1, 0, 0, 0, 0, "
     "1, 0, 0, 0, 0, 1, 0]"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"translate\": [0, 1e999, 0]}]}]}"),
     "bad.json:3:36: \"translate\"[1] must be a finite number, got 1e999"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"scale\": 1e30}, {\"scale\": 1e30}]}]}"),
     "bad.json:3:35: transform[1] makes the transform overflow single precision"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\",\n"
                    "   \"transform\": [{\"scale\": 1e-30}, {\"scale\": 1e-30}]}]}"),
     "bad.json:3:17: \"transform\" is singular or too close to it to invert in single precision (determinant 0)"},
    // --- quads and boxes ---
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [2, 0, 0], "
                    "\"material\": \"m\"}]}"),
     "bad.json:2:68: \"u\" and \"v\" must be non-zero and not parallel (the quad has no area)"},
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [3e38, 0, 0], \"v\": [0, 3e38, 0], "
                    "\"material\": \"m\"}]}"),
     "bad.json:2:71: the quad is too large: its area overflows single precision"},
    // 1e20 fits in a float; its square, which normalising u x v takes, does not.
    {__LINE__, TEXT("{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
                    " \"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1e10, 0, 0], \"v\": [0, 1e10, 0], "
                    "\"material\": \"m\"}]}"),
     "bad.json:2:71: the quad is too large: its area 1e+20 exceeds 1.84e+19, the largest whose square fits in single "
     "precision"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"material\": \"m\"}]}"),
     "bad.json:1:14: missing required key \"v\" in object 0 (quad)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"box\", \"min\": [0, 5, 0], \"max\": [1, 3, 1], "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:55: \"max\" must be greater than \"min\" in every coordinate, but \"max\"[1] = 3 <= \"min\"[1] = 5"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 0], "
                    "\"material\": \"m\"}]}"),
     "bad.json:1:55: \"max\" must be greater than \"min\" in every coordinate, but \"max\"[2] = 0 <= \"min\"[2] = 0"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"size\": 1}]}"),
     "bad.json:1:66: unknown key \"size\" in object 0 (box); expected one of: type, min, max, material, transform, "
     "transform2"},
    // --- motion blur: the shutter, center2, transform2 ---
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"shutter\": [0.5, 0.25]}}"),
     "bad.json:1:42: \"shutter\" closes before it opens ([0.5, 0.25]); expected [open, close] with open <= close"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"shutter\": [0, 2]}}"),
     "bad.json:1:46: \"shutter\"[1] must be a time in [0, 1], got 2"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"viewport\", \"shutter\": [-0.5, 1]}}"),
     "bad.json:1:45: \"shutter\"[0] must be a time in [0, 1], got -0.5"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"shutter\": [0]}}"),
     "bad.json:1:42: \"shutter\" must be an array of 2 times [open, close], got [0]"},
    {__LINE__, TEXT("{\"camera\": {\"type\": \"lookat\", \"shutter\": 0.5}}"),
     "bad.json:1:42: \"shutter\" must be an array of 2 times [open, close], got 0.5"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"center2\": [1, 2], \"radius\": 1, \"material\": \"m\"}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:65: \"center2\" must be an array of 3 numbers (x, y, z), got [1, 2]"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"center2\": [1, 2, 3], \"radius\": 1, \"material\": \"m\", \"transform\": [{\"translate\": [1, 0, 0]}]}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:65: \"center2\" cannot be combined with \"transform\" or \"transform2\": give both centres in world space, or move the sphere by \"transform2\" alone"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"center2\": [2e9, 0, 0], \"radius\": 1, \"material\": \"m\"}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:65: the moving sphere reaches 2e+09 on the x axis; glint renders within [-1e9, 1e9] on every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"m\", \"transform2\": [{\"translate\": [1, 0, 0]}]}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:97: a box cannot move: \"transform2\" is read for spheres and meshes only (a moving box can be a mesh)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\", \"transform2\": [{\"scale\": [-1, 1, 1]}]}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:98: \"transform2\" mirrors (determinant -1) where \"transform\" does not (determinant 1); expected two transforms that both mirror or neither, so that the motion between them never flattens the object"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\", \"transform2\": {\"translate\": [1, 0, 0]}}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:98: \"transform2\" must be an array of operations ({\"translate\": ...}, {\"rotate\": ...}, {\"scale\": ...} or {\"matrix\": ...}), got an object"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"material\": \"m\", \"transform2\": []}], \"materials\": {\"m\": {\"type\": \"lambertian\"}}}"),
     "bad.json:1:110: a quad cannot move: \"transform2\" is read for spheres and meshes only (a moving box can be a mesh)"},
    // --- meshes (files that exist or not are in test_files) ---
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"mesh\", \"file\": 3}]}"),
     "bad.json:1:39: \"file\" must be a non-empty string (a path relative to the scene file), got 3"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"mesh\"}]}"),
     "bad.json:1:14: missing required key \"file\" in object 0 (mesh)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"mesh\", \"file\": \"a.obj\", \"smooth\": true}]}"),
     "bad.json:1:48: unknown key \"smooth\" in object 0 (mesh); expected one of: type, file, mesh, material, transform, "
     "transform2, face_normals"},
    // --- participating media ---
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 0.1}]}"),
     "bad.json:1:14: missing required key \"boundary\" in object 0 (constant_medium)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 0,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}}]}"),
     "bad.json:1:53: \"density\" must be a number in (0, 1e30], got 0"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1e31,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}}]}"),
     "bad.json:1:53: \"density\" must be a number in (0, 1e30], got 1e31"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1, \"albedo\": 1.5,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}}]}"),
     "bad.json:1:66: \"albedo\" must be a number in [0, 1] or an array of 3 such numbers [r, g, b], got 1.5"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1, \"albedo\": \"smoke\",\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}}]}"),
     "bad.json:1:66: texture \"smoke\" is not defined (no named textures are defined)"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1, \"g\": 1,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}}]}"),
     "bad.json:1:61: \"g\" must be a number in (-1, 1), got 1"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1,\n"
                    " \"boundary\": {\"type\": \"mesh\", \"file\": \"a.obj\"}}]}"),
     "bad.json:2:23: \"type\" must be \"sphere\" or \"box\", got \"mesh\""},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": -1}}]}"),
     "bad.json:2:64: \"radius\" must be a finite number > 0, got -1"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\"}}]}"),
     "bad.json:2:67: unknown key \"material\" in the boundary (sphere) of object 0 (constant_medium); expected one "
     "of: type, center, radius, transform"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"homogeneous_medium\",\n"
                    " \"boundary\": {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 0, 1]}}]}"),
     "bad.json:2:55: \"max\" must be greater than \"min\" in every coordinate, but \"max\"[1] = 0 <= \"min\"[1] = 0"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"homogeneous_medium\", \"sigma_a\": 0, \"sigma_s\": [0, 0, 0],\n"
                    " \"boundary\": {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1]}}]}"),
     "bad.json:1:14: object 0 (homogeneous_medium) has no effect: \"sigma_a\" + \"sigma_s\" must be > 0 in some "
     "channel"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"homogeneous_medium\", \"sigma_s\": [1, -1, 1],\n"
                    " \"boundary\": {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1]}}]}"),
     "bad.json:1:60: \"sigma_s\"[1] must be a number in [0, 1e30], got -1"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"homogeneous_medium\", \"sigma_s\": 1, \"density\": 1,\n"
                    " \"boundary\": {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1]}}]}"),
     "bad.json:1:59: unknown key \"density\" in object 0 (homogeneous_medium); expected one of: type, boundary, "
     "sigma_a, sigma_s, g"},
    {__LINE__, TEXT("{\"objects\": [{\"type\": \"homogeneous_medium\", \"sigma_s\": 1,\n"
                    " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1,\n"
                    "  \"transform\": [{\"scale\": 2e9}]}}]}"),
     "bad.json:3:16: the transformed boundary reaches 2e+09 on the x axis; glint renders within [-1e9, 1e9] on "
     "every axis (beyond, squared distances overflow single precision and samples would be NaN)"},
    // --- lights ---
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"area\", \"intensity\": 1}]}"),
     "bad.json:1:22: \"type\" must be \"ambient\", \"point\", \"directional\" or \"spot\", got \"area\""},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"spot\", \"intensity\": 1}]}"),
     "bad.json:1:13: missing required key \"position\" in light 0 (spot)"},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"spot\", \"intensity\": 1, \"position\": [0, 0, 0], \"direction\": [0, -1, 0], "
                    "\"inner_angle\": 30, \"outer_angle\": 20}]}"),
     "bad.json:1:109: \"inner_angle\" (30) must be less than \"outer_angle\" (20)"},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"point\", \"position\": [2, 1, 0]}]}"),
     "bad.json:1:13: missing required key \"intensity\" in light 0 (point)"},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"ambient\", \"intensity\": -0.2}]}"),
     "bad.json:1:46: \"intensity\" must be a finite number >= 0 or an array of 3 such numbers [r, g, b], got -0.2"},
    {__LINE__, TEXT("{\"lights\": [{\"type\": \"directional\", \"intensity\": 0.2, \"direction\": [0, 0, 0]}]}"),
     "bad.json:1:68: \"direction\" must be a non-zero vector, got [0, 0, 0]"},
};

#endif
