/* SPDX-License-Identifier: Apache-2.0 */
/* The MIT-mode codec: pure arithmetic over caller storage, no OS. */
#include "roz/port/mit_codec.h"

#include <math.h>
#include <string.h>

/* ---- private ------------------------------------------------------------- */

static const char *const layout_names[ROZ_MIT_REPLY_LAYOUT_COUNT_] = {
    "basic",
    "temperature_error",
};

/* 2^bits - 1; a width outside 1..ROZ_MIT_MAX_BITS counts as the nearest one */
static uint32_t top_code(unsigned bits)
{
    bits = bits < 1u ? 1u : (bits > ROZ_MIT_MAX_BITS ? ROZ_MIT_MAX_BITS : bits);
    return (1u << bits) - 1u;
}

/* The value nearest 0 within the range: what a non-finite value becomes. */
static double nearest_zero(const roz_mit_range_t *r)
{
    return r->min > 0.0 ? r->min : (r->max < 0.0 ? r->max : 0.0);
}

/* round((x - min) * top / (max - min)), halves up, for min <= x <= max. The
 * fraction is taken from floor(t) exactly (t - floor(t) is exact), so a
 * value just below a half never rounds up through a rounded t + 0.5. */
static uint16_t code_of(double x, const roz_mit_range_t *r, uint32_t top)
{
    double t = (x - r->min) * (double)top / (r->max - r->min);
    double whole = floor(t);
    uint32_t code = (uint32_t)whole;
    if (t - whole >= 0.5)
        code++;
    return (uint16_t)(code > top ? top : code);
}

static uint32_t field(double x, const roz_mit_range_t *r, unsigned bits, uint16_t *code,
                      uint32_t sat_bit, uint32_t nonfinite_bit)
{
    uint32_t what = roz_mit_codec_encode(x, r, bits, code);
    return (what & ROZ_MIT_CODE_SATURATED ? sat_bit : 0u) |
           (what & ROZ_MIT_CODE_NONFINITE ? nonfinite_bit : 0u);
}

static uint16_t be12(const uint8_t *hi, int high_half)
{
    /* a 12-bit field that starts at a byte (high_half) or in its low nibble */
    return high_half ? (uint16_t)((hi[0] << 4) | (hi[1] >> 4))
                     : (uint16_t)(((hi[0] & 0x0Fu) << 8) | hi[1]);
}

/* ---- public -------------------------------------------------------------- */

int roz_mit_codec_range_valid(const roz_mit_range_t *r)
{
    /* (x - min) * top must stay finite for every x in the range */
    return r != NULL && isfinite(r->min) && isfinite(r->max) && r->min < r->max &&
           isfinite((r->max - r->min) * (double)(1u << ROZ_MIT_MAX_BITS));
}

int roz_mit_codec_ranges_valid(const roz_mit_ranges_t *r)
{
    return r != NULL && roz_mit_codec_range_valid(&r->position) &&
           roz_mit_codec_range_valid(&r->velocity) && roz_mit_codec_range_valid(&r->kp) &&
           roz_mit_codec_range_valid(&r->kd) && roz_mit_codec_range_valid(&r->torque);
}

uint32_t roz_mit_codec_encode(double x, const roz_mit_range_t *r, unsigned bits, uint16_t *code)
{
    uint32_t top = top_code(bits);

    if (!isfinite(x)) {
        *code = code_of(nearest_zero(r), r, top);
        return ROZ_MIT_CODE_NONFINITE;
    }
    if (x > r->max) {
        *code = (uint16_t)top;
        return ROZ_MIT_CODE_SATURATED;
    }
    if (x < r->min) {
        *code = 0;
        return ROZ_MIT_CODE_SATURATED;
    }
    *code = code_of(x, r, top);
    return 0u;
}

double roz_mit_codec_decode(uint16_t code, const roz_mit_range_t *r, unsigned bits)
{
    uint32_t top = top_code(bits);
    uint32_t c = code & top;

    if (c == top)
        return r->max;
    return r->min + (double)c * (r->max - r->min) / (double)top;
}

double roz_mit_codec_step(const roz_mit_range_t *r, unsigned bits)
{
    return (r->max - r->min) / (double)top_code(bits);
}

uint32_t roz_mit_codec_quantize(const roz_mit_ranges_t *r, const roz_mit_command_t *c,
                                roz_mit_codes_t *out)
{
    uint32_t what = 0;

    what |= field(c->position, &r->position, ROZ_MIT_POSITION_BITS, &out->position,
                  ROZ_MIT_SAT_POSITION, ROZ_MIT_NONFINITE_POSITION);
    what |= field(c->velocity, &r->velocity, ROZ_MIT_VELOCITY_BITS, &out->velocity,
                  ROZ_MIT_SAT_VELOCITY, ROZ_MIT_NONFINITE_VELOCITY);
    what |= field(c->kp, &r->kp, ROZ_MIT_KP_BITS, &out->kp, ROZ_MIT_SAT_KP,
                  ROZ_MIT_NONFINITE_KP);
    what |= field(c->kd, &r->kd, ROZ_MIT_KD_BITS, &out->kd, ROZ_MIT_SAT_KD,
                  ROZ_MIT_NONFINITE_KD);
    what |= field(c->torque, &r->torque, ROZ_MIT_TORQUE_BITS, &out->torque,
                  ROZ_MIT_SAT_TORQUE, ROZ_MIT_NONFINITE_TORQUE);
    /* no gain toward a target that is not a number */
    if (what & ROZ_MIT_NONFINITE_POSITION)
        out->kp = 0;
    if (what & ROZ_MIT_NONFINITE_VELOCITY)
        out->kd = 0;
    return what;
}

uint32_t roz_mit_codec_pack_codes(const roz_mit_codes_t *c, uint8_t out[ROZ_MIT_FRAME_BYTES])
{
    uint16_t p = c->position;
    uint16_t v = c->velocity & 0xFFFu, kp = c->kp & 0xFFFu, kd = c->kd & 0xFFFu;
    uint16_t t = c->torque & 0xFFFu;
    uint32_t what = 0;

    if (p == 0xFFFFu && v == 0xFFFu && kp == 0xFFFu && kd == 0xFFFu && t >= 0xFFCu &&
        t <= 0xFFEu) {
        t = 0xFFBu; /* FF FF FF FF FF FF FF FC..FE: a special frame */
        what = ROZ_MIT_AVOIDED_SPECIAL;
    }
    out[0] = (uint8_t)(p >> 8);
    out[1] = (uint8_t)(p & 0xFFu);
    out[2] = (uint8_t)(v >> 4);
    out[3] = (uint8_t)(((v & 0x0Fu) << 4) | (kp >> 8));
    out[4] = (uint8_t)(kp & 0xFFu);
    out[5] = (uint8_t)(kd >> 4);
    out[6] = (uint8_t)(((kd & 0x0Fu) << 4) | (t >> 8));
    out[7] = (uint8_t)(t & 0xFFu);
    return what;
}

uint32_t roz_mit_codec_pack(const roz_mit_ranges_t *r, const roz_mit_command_t *c,
                            uint8_t out[ROZ_MIT_FRAME_BYTES])
{
    roz_mit_codes_t codes;
    uint32_t what = roz_mit_codec_quantize(r, c, &codes);
    return what | roz_mit_codec_pack_codes(&codes, out);
}

size_t roz_mit_codec_reply_bytes(roz_mit_reply_layout_t layout)
{
    switch (layout) {
    case ROZ_MIT_REPLY_BASIC:
        return 6;
    case ROZ_MIT_REPLY_TEMP_ERROR:
        return 8;
    default:
        return 0;
    }
}

int roz_mit_codec_unpack(const roz_mit_ranges_t *r, roz_mit_reply_layout_t layout,
                         const uint8_t *data, size_t len, roz_mit_reply_t *out)
{
    size_t need = roz_mit_codec_reply_bytes(layout);
    roz_mit_reply_t rep;

    if (need == 0 || data == NULL || len < need)
        return ROZ_EINVAL;
    memset(&rep, 0, sizeof rep);
    rep.id = data[0];
    rep.position_code = (uint16_t)((data[1] << 8) | data[2]);
    rep.velocity_code = be12(&data[3], 1);
    rep.torque_code = be12(&data[4], 0);
    rep.position = roz_mit_codec_decode(rep.position_code, &r->position, ROZ_MIT_POSITION_BITS);
    rep.velocity = roz_mit_codec_decode(rep.velocity_code, &r->velocity, ROZ_MIT_VELOCITY_BITS);
    rep.torque = roz_mit_codec_decode(rep.torque_code, &r->torque, ROZ_MIT_TORQUE_BITS);
    if (layout == ROZ_MIT_REPLY_TEMP_ERROR) {
        rep.temperature = data[6];
        rep.error = data[7];
    }
    *out = rep;
    return ROZ_OK;
}

void roz_mit_codec_special(roz_mit_special_t which, uint8_t out[ROZ_MIT_FRAME_BYTES])
{
    memset(out, 0xFF, ROZ_MIT_FRAME_BYTES - 1u);
    out[ROZ_MIT_FRAME_BYTES - 1u] = (uint8_t)which;
}

int roz_mit_codec_special_of(const uint8_t *data, size_t len)
{
    if (data == NULL || len != ROZ_MIT_FRAME_BYTES)
        return 0;
    for (size_t i = 0; i + 1u < ROZ_MIT_FRAME_BYTES; i++) {
        if (data[i] != 0xFFu)
            return 0;
    }
    uint8_t last = data[ROZ_MIT_FRAME_BYTES - 1u];
    return last >= ROZ_MIT_ENTER_MOTOR_MODE && last <= ROZ_MIT_SET_ZERO ? (int)last : 0;
}

const char *roz_mit_codec_layout_name(roz_mit_reply_layout_t layout)
{
    return (unsigned)layout < (unsigned)ROZ_MIT_REPLY_LAYOUT_COUNT_ ? layout_names[layout] : NULL;
}

int roz_mit_codec_layout_parse(const char *name, roz_mit_reply_layout_t *out)
{
    for (unsigned i = 0; name != NULL && i < (unsigned)ROZ_MIT_REPLY_LAYOUT_COUNT_; i++) {
        if (strcmp(layout_names[i], name) == 0) {
            *out = (roz_mit_reply_layout_t)i;
            return ROZ_OK;
        }
    }
    return ROZ_EINVAL;
}
