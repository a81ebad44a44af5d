/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/identity.h"

#include <string.h>

#include "roz/format.h"

/* ---- private: the interface hash ------------------------------------------ */

/* FNV-1a 64: enough to tell two channel tables apart by accident (a chance
 * of about 2^-64 for two different tables), short enough to print, a few
 * lines without tables on any target. It is no defence against a module
 * written to lie, and is not meant to be. */
#define FNV64_OFFSET 0xcbf29ce484222325ull
#define FNV64_PRIME  0x100000001b3ull

/* The first bytes hashed (codegen/README.md, "Manifest identity"). */
static const char interface_tag[] = "roz-interface-v1";

static void fnv_bytes(uint64_t *h, const void *p, size_t n)
{
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++) {
        *h ^= b[i];
        *h *= FNV64_PRIME;
    }
}

/* Integers are hashed little-endian whatever the host's byte order. */
static void fnv_le(uint64_t *h, uint64_t v, unsigned bytes)
{
    for (unsigned i = 0; i < bytes; i++) {
        uint8_t b = (uint8_t)(v >> (8 * i));
        fnv_bytes(h, &b, 1);
    }
}

static void fnv_text(uint64_t *h, const char *s)
{
    size_t n = s != NULL ? strlen(s) : 0;
    fnv_le(h, (uint64_t)n, 4);
    fnv_bytes(h, s, n);
}

/* A limit's IEEE 754 binary64 bits; -0.0 is the same limit as 0.0. (Hosts
 * whose doubles and integers differ in byte order are not supported.) */
static void fnv_limit(uint64_t *h, double x)
{
    uint64_t bits;
    _Static_assert(sizeof x == sizeof bits, "double must be IEEE 754 binary64");
    if (x == 0.0)
        x = 0.0;
    memcpy(&bits, &x, sizeof bits);
    fnv_le(h, bits, 8);
}

static void fnv_channels(uint64_t *h, const roz_channel_t *list, uint16_t n)
{
    for (uint16_t i = 0; list != NULL && i < n; i++) {
        fnv_text(h, list[i].name);
        fnv_text(h, roz_interface_name(list[i].type));
        fnv_text(h, list[i].unit);
        fnv_limit(h, list[i].min);
        fnv_limit(h, list[i].max);
    }
}

/* ---- private: the roz.manifest section ------------------------------------ */

/* A record: u8 version (1), u8 length of robot_id, robot_id, u64 hash LE. */
#define RECORD_FIXED 10u /* bytes of a record besides robot_id */

/* A message into (err, errlen), either of which may be NULL/0. */
#define ERR(...)                                   \
    do {                                           \
        if (err != NULL && errlen > 0)             \
            roz_format(err, errlen, __VA_ARGS__);  \
    } while (0)

/* An unsigned LEB128 of at most 32 bits at *at; 0 when malformed or cut. */
static int rd_u32(const uint8_t *p, size_t len, size_t *at, uint32_t *out)
{
    uint32_t v = 0;
    for (unsigned shift = 0; shift < 35; shift += 7) {
        if (*at >= len)
            return 0;
        uint8_t b = p[(*at)++];
        if (shift == 28 && (b & 0x70) != 0)
            return 0;
        v |= (uint32_t)(b & 0x7f) << shift;
        if ((b & 0x80) == 0) {
            *out = v;
            return 1;
        }
    }
    return 0;
}

static int id_char_ok(uint8_t c, int first)
{
    return (c >= 'a' && c <= 'z') || (!first && ((c >= '0' && c <= '9') || c == '_'));
}

/* A robot_id from a module, for a message: printable ASCII kept, other
 * bytes as \xNN. */
static const char *show_id(const uint8_t *s, size_t n, char *out, size_t outlen)
{
    size_t k = 0;
    for (size_t i = 0; i < n && k + 5 < outlen; i++) {
        if (s[i] >= 0x20 && s[i] < 0x7f && s[i] != '\\' && s[i] != '\'')
            out[k++] = (char)s[i];
        else
            k += (size_t)roz_format(out + k, outlen - k, "\\x%02x", s[i]);
    }
    out[k] = '\0';
    return out;
}

/* A walk through a module's sections to the custom ones named alike: the
 * next section's offset (0: the module's start), the first found's, and the
 * one found: its offset (after its size), its content (after its name), its
 * end. */
typedef struct walk {
    size_t at, first, body, p, end;
} walk_t;

/* The next custom section named @p name, as both readers below walk a
 * module (w zeroed at first; err emptied then): 1 with its place in *w, 0
 * at the module's end, -1 with err saying why the module is malformed or
 * has a second such section (@p one: what that message adds). */
static int next_section(const uint8_t *wasm, size_t len, const char *name, const char *one,
                        walk_t *w, char *err, size_t errlen)
{
    static const uint8_t magic[8] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    size_t name_len = strlen(name);

    if (w->at == 0) {
        if (err != NULL && errlen > 0)
            err[0] = '\0';
        if (wasm == NULL || len < sizeof magic || memcmp(wasm, magic, sizeof magic) != 0) {
            ERR("not a WebAssembly 1.0 binary (bad magic or version)");
            return -1;
        }
        w->at = sizeof magic;
    }
    while (w->at < len) {
        size_t sec_at = w->at;
        uint8_t sec = wasm[w->at++];
        uint32_t size = 0, n = 0;
        if (!rd_u32(wasm, len, &w->at, &size) || size > len - w->at) {
            ERR("malformed module: section %u at offset %zu runs past the end", (unsigned)sec,
                sec_at);
            return -1;
        }
        size_t body = w->at, end = w->at + size, p = body;
        w->at = end;
        if (sec != 0)
            continue;
        if (!rd_u32(wasm, end, &p, &n) || n > end - p) {
            ERR("custom section at offset %zu: malformed name", body);
            return -1;
        }
        if (n != name_len || memcmp(wasm + p, name, n) != 0)
            continue;
        if (w->first != 0) {
            ERR("two custom sections \"%s\" (at offsets %zu and %zu)%s", name, w->first, body,
                one);
            return -1;
        }
        w->first = w->body = body;
        w->p = p + n;
        w->end = end;
        return 1;
    }
    return 0;
}

/* The records of a section's content (after its name): one or more copies
 * of the same record, since wasm-ld joins the sections of all object files
 * built with the same header. Says in err why they are malformed. */
static int parse_records(const uint8_t *p, size_t n, roz_identity_t *id, char *err,
                         size_t errlen)
{
    char shown[4 * ROZ_IDENTITY_MAX_ID + 1];

    if (n == 0) {
        ERR("empty (a version-%u record was expected)", ROZ_IDENTITY_VERSION);
        return ROZ_EINVAL;
    }
    for (size_t at = 0; at < n;) {
        size_t left = n - at;
        if (p[at] != ROZ_IDENTITY_VERSION) {
            ERR("record version %u at byte %zu; this roz reads version %u (rebuild the "
                "controller with this roz's rozgen)", (unsigned)p[at], at, ROZ_IDENTITY_VERSION);
            return ROZ_EINVAL;
        }
        size_t idlen = left >= 2 ? p[at + 1] : 0;
        if (left < 2 || idlen == 0 || idlen > ROZ_IDENTITY_MAX_ID) {
            ERR("record at byte %zu: a robot_id of %zu bytes (1..%u)", at, idlen,
                ROZ_IDENTITY_MAX_ID);
            return ROZ_EINVAL;
        }
        if (left < RECORD_FIXED + idlen) {
            ERR("record at byte %zu cut short: %zu bytes of %zu", at, left, RECORD_FIXED + idlen);
            return ROZ_EINVAL;
        }
        const uint8_t *rid = p + at + 2;
        for (size_t i = 0; i < idlen; i++) {
            if (!id_char_ok(rid[i], i == 0)) {
                ERR("record at byte %zu: robot_id '%s' is not [a-z][a-z0-9_]*", at,
                    show_id(rid, idlen, shown, sizeof shown));
                return ROZ_EINVAL;
            }
        }
        uint64_t hash = 0;
        for (unsigned i = 0; i < 8; i++)
            hash |= (uint64_t)rid[idlen + i] << (8 * i);
        if (!id->present) {
            id->present = 1;
            memcpy(id->robot_id, rid, idlen);
            id->robot_id[idlen] = '\0';
            id->hash = hash;
        } else if (strlen(id->robot_id) != idlen || memcmp(id->robot_id, rid, idlen) != 0 ||
                   id->hash != hash) {
            ERR("two different records: '%s' (hash %016llx) and '%s' (hash %016llx)",
                id->robot_id, (unsigned long long)id->hash,
                show_id(rid, idlen, shown, sizeof shown), (unsigned long long)hash);
            return ROZ_EINVAL;
        }
        at += RECORD_FIXED + idlen;
    }
    return ROZ_OK;
}

/* ---- public -------------------------------------------------------------- */

uint64_t roz_manifest_interface_hash(const roz_manifest_t *m)
{
    uint64_t h = FNV64_OFFSET;
    fnv_bytes(&h, interface_tag, sizeof interface_tag - 1);
    fnv_le(&h, m != NULL ? m->n_commands : 0u, 4);
    fnv_le(&h, m != NULL ? m->n_states : 0u, 4);
    if (m != NULL) {
        fnv_channels(&h, m->commands, m->n_commands);
        fnv_channels(&h, m->states, m->n_states);
        /* inputs are read as states n_states + k: hashed after them, and
         * only when there are any, so a manifest without inputs keeps its
         * hash */
        if (m->n_inputs > 0) {
            fnv_le(&h, m->n_inputs, 4);
            fnv_channels(&h, m->inputs, m->n_inputs);
        }
    }
    return h;
}

int roz_identity_read(const uint8_t *wasm, size_t len, roz_identity_t *id, char *err,
                      size_t errlen)
{
    static const char name[] = ROZ_IDENTITY_SECTION;
    char why[ROZ_CFG_ERROR_LEN];
    walk_t w = { 0 };
    int rc;

    if (id == NULL)
        return ROZ_EINVAL;
    memset(id, 0, sizeof *id);
    while ((rc = next_section(wasm, len, name, "; a controller carries one identity", &w, err,
                              errlen)) > 0) {
        if (parse_records(wasm + w.p, w.end - w.p, id, why, sizeof why) != ROZ_OK) {
            ERR("custom section \"%s\" at offset %zu: %s", name, w.body, why);
            rc = -1;
            break;
        }
    }
    if (rc < 0)
        memset(id, 0, sizeof *id);
    return rc == 0 ? ROZ_OK : ROZ_EINVAL;
}

roz_identity_match_t roz_identity_check(const roz_identity_t *id, const roz_manifest_t *m,
                                        char *msg, size_t len)
{
    if (msg != NULL && len > 0)
        msg[0] = '\0';
    if (id == NULL || !id->present || m == NULL)
        return ROZ_IDENTITY_NONE;
    uint64_t ours = roz_manifest_interface_hash(m);
    const char *our_id = m->robot_id != NULL ? m->robot_id : "";
    if (strcmp(id->robot_id, our_id) != 0) {
        if (msg != NULL && len > 0)
            roz_format(msg, len, "controller built for robot '%s' (hash %016llx), this robot is "
                                 "'%s' (hash %016llx)", id->robot_id,
                       (unsigned long long)id->hash, our_id, (unsigned long long)ours);
        return ROZ_IDENTITY_OTHER_ROBOT;
    }
    if (id->hash != ours) {
        if (msg != NULL && len > 0)
            roz_format(msg, len, "controller built for robot '%s' (hash %016llx) before its "
                                 "channel table changed: this robot's table has hash %016llx",
                       our_id, (unsigned long long)id->hash, (unsigned long long)ours);
        return ROZ_IDENTITY_TABLE_CHANGED;
    }
    return ROZ_IDENTITY_SAME;
}

/* The section "roz.fuel": a declaration is a record of 9 bytes, repeated
 * once per object file that made it (wasm-ld joins them), all equal. */
int roz_identity_read_fuel(const uint8_t *wasm, size_t len, uint64_t *fuel, char *err,
                           size_t errlen)
{
    static const char name[] = ROZ_FUEL_SECTION;
    walk_t w = { 0 };
    int rc;

    if (fuel == NULL)
        return ROZ_EINVAL;
    *fuel = 0;
    while ((rc = next_section(wasm, len, name, "", &w, err, errlen)) > 0) {
        size_t p = w.p, end = w.end, body = w.body;
        if (p == end) {
            ERR("custom section \"%s\" at offset %zu: empty", name, body);
            goto refused;
        }
        for (; p < end; p += 9) {
            uint64_t units = 0;
            if (wasm[p] != ROZ_FUEL_VERSION) {
                ERR("custom section \"%s\" at offset %zu: record version %u; this roz reads "
                    "version %u", name, body, (unsigned)wasm[p], ROZ_FUEL_VERSION);
                goto refused;
            }
            if (end - p < 9) {
                ERR("custom section \"%s\" at offset %zu: a record cut short", name, body);
                goto refused;
            }
            for (unsigned i = 0; i < 8; i++)
                units |= (uint64_t)wasm[p + 1 + i] << (8 * i);
            /* 2^64 - 1 is ROZ_BUDGET_OFF: only the integrator runs a module
             * unmetered (test_nn_budget_malformed) */
            if (units == 0 || units == UINT64_MAX || (*fuel != 0 && units != *fuel)) {
                ERR("custom section \"%s\" at offset %zu: %s", name, body,
                    units == 0            ? "0 units declared"
                    : units == UINT64_MAX ? "18446744073709551615 units declared (the budget "
                                            "'off': a module cannot declare itself unmetered)"
                                          : "two different declarations");
                goto refused;
            }
            *fuel = units;
        }
    }
    if (rc == 0)
        return ROZ_OK;
refused:
    *fuel = 0;
    return ROZ_EINVAL;
}
