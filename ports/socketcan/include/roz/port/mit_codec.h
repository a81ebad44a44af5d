/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/mit_codec.h
 * @brief The "MIT mode" frames of quasi-direct-drive CAN actuators: packing a
 *        command, unpacking a reply, the special frames. Pure and portable:
 *        no OS, no heap, no state; it builds for a microcontroller as well.
 *
 * docs/ports/socketcan.md ("The frames") gives the bit layout, the linear
 * quantisation and its round-trip error, saturation (ROZ_MIT_SAT_*),
 * non-finite values (ROZ_MIT_NONFINITE_*) and the special frames a command
 * must never look like (ROZ_MIT_AVOIDED_SPECIAL).
 *
 * Context: every function is pure; any thread, ISR, tick; RT-safe.
 */
#ifndef ROZ_PORT_MIT_CODEC_H
#define ROZ_PORT_MIT_CODEC_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Bytes of a command frame and of a special frame. */
#define ROZ_MIT_FRAME_BYTES 8u
/** Widths of the fields, bits. */
#define ROZ_MIT_POSITION_BITS 16u
#define ROZ_MIT_VELOCITY_BITS 12u
#define ROZ_MIT_KP_BITS 12u
#define ROZ_MIT_KD_BITS 12u
#define ROZ_MIT_TORQUE_BITS 12u
/** The widest field a code may have. */
#define ROZ_MIT_MAX_BITS 16u

/** What encoding one value reports. */
#define ROZ_MIT_CODE_SATURATED 1u /**< outside the range: the nearest end was sent */
#define ROZ_MIT_CODE_NONFINITE 2u /**< NaN or infinite: the code nearest 0 was sent */

/** What packing a command reports, one bit per field and kind. */
#define ROZ_MIT_SAT_POSITION (1u << 0)
#define ROZ_MIT_SAT_VELOCITY (1u << 1)
#define ROZ_MIT_SAT_KP (1u << 2)
#define ROZ_MIT_SAT_KD (1u << 3)
#define ROZ_MIT_SAT_TORQUE (1u << 4)
#define ROZ_MIT_NONFINITE_POSITION (1u << 5)
#define ROZ_MIT_NONFINITE_VELOCITY (1u << 6)
#define ROZ_MIT_NONFINITE_KP (1u << 7)
#define ROZ_MIT_NONFINITE_KD (1u << 8)
#define ROZ_MIT_NONFINITE_TORQUE (1u << 9)
#define ROZ_MIT_AVOIDED_SPECIAL (1u << 10) /**< the torque code moved off a special frame */
/** Any saturation. */
#define ROZ_MIT_SAT_ANY 0x1Fu
/** Any non-finite value. */
#define ROZ_MIT_NONFINITE_ANY 0x3E0u

/** A value's range, [min, max]; finite, min < max. */
typedef struct roz_mit_range {
    double min;
    double max;
} roz_mit_range_t;

/** An actuator's ranges, in its own units (rad, rad/s, N.m/rad, N.m.s/rad,
 *  N.m; output side), as its firmware maps them. */
typedef struct roz_mit_ranges {
    roz_mit_range_t position;
    roz_mit_range_t velocity;
    roz_mit_range_t kp;
    roz_mit_range_t kd;
    roz_mit_range_t torque;
} roz_mit_ranges_t;

/** A command in the actuator's units: torque = kp (position - q) +
 *  kd (velocity - dq) + torque, computed by the actuator. */
typedef struct roz_mit_command {
    double position;
    double velocity;
    double kp;
    double kd;
    double torque;
} roz_mit_command_t;

/** A command's codes (each below 2^width). */
typedef struct roz_mit_codes {
    uint16_t position;
    uint16_t velocity;
    uint16_t kp;
    uint16_t kd;
    uint16_t torque;
} roz_mit_codes_t;

/** What follows position, velocity and torque in a reply. */
typedef enum roz_mit_reply_layout {
    /** Nothing: 6 bytes (id, position, velocity, torque), as the open
     *  reference motor firmware sends. Longer frames are read as 6 bytes. */
    ROZ_MIT_REPLY_BASIC = 0,
    /** Byte 6 the temperature (a raw byte: its scale is the firmware's),
     *  byte 7 an error code, 0 for none: 8 bytes. */
    ROZ_MIT_REPLY_TEMP_ERROR,
    ROZ_MIT_REPLY_LAYOUT_COUNT_ /**< number of layouts; not a layout */
} roz_mit_reply_layout_t;

/** An unpacked reply. */
typedef struct roz_mit_reply {
    uint8_t  id;            /**< the id byte: the actuator's CAN id, low 8 bits */
    uint16_t position_code; /**< as sent */
    uint16_t velocity_code;
    uint16_t torque_code;
    double   position;      /**< decoded with the actuator's ranges */
    double   velocity;
    double   torque;
    uint8_t  temperature;   /**< ROZ_MIT_REPLY_TEMP_ERROR: byte 6, raw; else 0 */
    uint8_t  error;         /**< ROZ_MIT_REPLY_TEMP_ERROR: byte 7; else 0 */
} roz_mit_reply_t;

/** The special frames: their last byte. */
typedef enum roz_mit_special {
    ROZ_MIT_ENTER_MOTOR_MODE = 0xFC,
    ROZ_MIT_EXIT_MOTOR_MODE = 0xFD,
    ROZ_MIT_SET_ZERO = 0xFE,
} roz_mit_special_t;

/**
 * @brief Whether @p r is a usable range: both ends finite, min < max, and
 *        (max - min) * 2^16 finite.
 * Context: any; pure.
 */
int roz_mit_codec_range_valid(const roz_mit_range_t *r);

/** @brief Whether all five ranges of @p r are usable.
 *  Context: any; pure. */
int roz_mit_codec_ranges_valid(const roz_mit_ranges_t *r);

/**
 * @brief Encode one value.
 * @param[in]  x     the value
 * @param[in]  r     its range (roz_mit_codec_range_valid())
 * @param[in]  bits  the field's width, 1..ROZ_MIT_MAX_BITS (others count as
 *                   the nearest of these)
 * @param[out] code  the code, 0 .. 2^bits - 1
 * @return 0, ROZ_MIT_CODE_SATURATED or ROZ_MIT_CODE_NONFINITE
 * Context: any; pure.
 */
uint32_t roz_mit_codec_encode(double x, const roz_mit_range_t *r, unsigned bits, uint16_t *code);

/**
 * @brief Decode one code (bits above @p bits are ignored).
 * @return min + code * (max - min) / (2^bits - 1); exactly min for 0 and
 *         max for the top code
 * Context: any; pure.
 */
double roz_mit_codec_decode(uint16_t code, const roz_mit_range_t *r, unsigned bits);

/** @brief The quantisation step of a field: (max - min) / (2^bits - 1).
 *  Context: any; pure. */
double roz_mit_codec_step(const roz_mit_range_t *r, unsigned bits);

/**
 * @brief Encode a command's five values.
 * @return the ROZ_MIT_SAT_* and ROZ_MIT_NONFINITE_* bits of what happened
 * Context: any; pure.
 */
uint32_t roz_mit_codec_quantize(const roz_mit_ranges_t *r, const roz_mit_command_t *c,
                                roz_mit_codes_t *out);

/**
 * @brief Lay codes out as a command frame (codes are cut to their widths).
 * @return ROZ_MIT_AVOIDED_SPECIAL when the torque code was moved off a
 *         special frame, else 0
 * Context: any; pure.
 */
uint32_t roz_mit_codec_pack_codes(const roz_mit_codes_t *c, uint8_t out[ROZ_MIT_FRAME_BYTES]);

/**
 * @brief Encode and lay out a command: roz_mit_codec_quantize() then
 *        roz_mit_codec_pack_codes().
 * @return the bits both report
 * Context: any; pure.
 */
uint32_t roz_mit_codec_pack(const roz_mit_ranges_t *r, const roz_mit_command_t *c,
                            uint8_t out[ROZ_MIT_FRAME_BYTES]);

/** @brief Bytes a reply of @p layout needs: 6 or 8; 0 for an unknown layout.
 *  Context: any; pure. */
size_t roz_mit_codec_reply_bytes(roz_mit_reply_layout_t layout);

/**
 * @brief Unpack a reply.
 * @param[in]  r       the actuator's ranges
 * @param[in]  layout  its reply layout
 * @param[in]  data    the frame's data bytes
 * @param[in]  len     how many (a CAN frame's length, 0..8)
 * @param[out] out     the reply; untouched on error
 * @retval ROZ_OK     unpacked
 * @retval ROZ_EINVAL shorter than the layout needs, or an unknown layout
 * Context: any; pure.
 */
int roz_mit_codec_unpack(const roz_mit_ranges_t *r, roz_mit_reply_layout_t layout,
                         const uint8_t *data, size_t len, roz_mit_reply_t *out);

/** @brief A special frame: seven 0xFF bytes, then @p which.
 *  Context: any; pure. */
void roz_mit_codec_special(roz_mit_special_t which, uint8_t out[ROZ_MIT_FRAME_BYTES]);

/**
 * @brief Which special frame @p data is.
 * @return ROZ_MIT_ENTER_MOTOR_MODE, ROZ_MIT_EXIT_MOTOR_MODE or
 *         ROZ_MIT_SET_ZERO; 0 when it is none (or not 8 bytes)
 * Context: any; pure.
 */
int roz_mit_codec_special_of(const uint8_t *data, size_t len);

/** @brief "basic", "temperature_error"; NULL for an unknown layout.
 *  Context: any; pure. */
const char *roz_mit_codec_layout_name(roz_mit_reply_layout_t layout);

/**
 * @brief Parse a layout name.
 * @retval ROZ_OK     parsed
 * @retval ROZ_EINVAL unknown
 * Context: any; pure.
 */
int roz_mit_codec_layout_parse(const char *name, roz_mit_reply_layout_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_MIT_CODEC_H */
