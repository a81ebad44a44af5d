/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/joy.h
 * @brief A joystick message (sensor_msgs/Joy: an array of axes and an array
 *        of buttons) as the remote (roz/operator.h), through a map written
 *        as text: one rule for every reader of a Joy (the ROS 2 ports'
 *        /joy and their parameter joy_map, rozrun --teleop's Foxglove
 *        Joystick panel). Transport-free: no DDS, no socket.
 *
 * A map is entries `FIELD=SOURCE` separated by spaces. FIELD is a field of
 * the remote without its "remote." (lx, ly, rx, ry, l2, r2, btn.NAME);
 * SOURCE is `aN` (axis N), `-aN` (axis N negated) or `bN` (button N), N
 * decimal below ROZ_JOY_MAX without a leading zero. A field named twice, an
 * unknown field or a malformed source is refused; a field not named is 0.
 */
#ifndef ROZ_JOY_H
#define ROZ_JOY_H

#include <stddef.h>
#include <stdint.h>

#include "roz/operator.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most axes, and most buttons, of a Joy a map may name (ROS 2's joy
 *  game_controller_node sends 6 axes and 21 buttons, a browser's standard
 *  gamepad 4 axes and 17 buttons). */
#define ROZ_JOY_MAX 32

/** Where a remote's field comes from in a Joy. */
typedef struct roz_joy_source {
    uint8_t kind;  /**< 0: nowhere (the field is 0); 'a': an axis; 'b': a button */
    int8_t  sign;  /**< an axis's: 1 or -1 */
    uint8_t index; /**< into axes or buttons, < ROZ_JOY_MAX */
} roz_joy_source_t;

/** The remote's fields as a Joy gives them, indexed by roz_operator_field_t
 *  (its remote fields; the others unused). */
typedef struct roz_joy_map {
    roz_joy_source_t field[ROZ_OPERATOR_FIELD_COUNT_];
} roz_joy_map_t;

/**
 * @brief Read a map (the file comment's grammar).
 * @param what  where the map comes from, the start of the error
 *              ("parameter joy_map")
 * @param[out] err `WHAT = "TEXT": "ENTRY": why`, naming the bad entry
 * @retval ROZ_OK     @p map set
 * @retval ROZ_EINVAL refused (@p map all 0), or a NULL @p text
 * Context: start-up; no heap.
 */
int roz_joy_map_parse(const char *what, const char *text, roz_joy_map_t *map, char *err,
                      size_t errlen);

/**
 * @brief The remote frame of one Joy through @p map: a stick or trigger
 *        takes its axis (sign applied) or button (0 or 1); a button is
 *        pressed when its button is not 0, or its axis (sign applied) is
 *        above 0.5.
 * @retval ROZ_OK     @p out set
 * @retval ROZ_ENOSPC more than ROZ_JOY_MAX axes, or buttons: refused whole,
 *                    whatever the map names (no pad has so many; a reader
 *                    counts it apart: roz_ros2_counters_t operator_oversized)
 * @retval ROZ_ERANGE the map names an axis or a button the message has not
 * @retval ROZ_EINVAL an axis the map names is not finite
 * Context: any (a receive thread); RT-safe, no heap, O(fields).
 */
int roz_joy_remote(const roz_joy_map_t *map, const float *axes, uint32_t n_axes,
                   const int32_t *buttons, uint32_t n_buttons, roz_operator_remote_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_JOY_H */
