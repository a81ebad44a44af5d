/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the G1 port: the manifest <-> unitree_hg binding and the
 * conversions, pure functions over the native structs (no DDS, no threads). */
#ifndef ROZ_G1_MAP_H
#define ROZ_G1_MAP_H

#include <stddef.h>
#include <stdint.h>

#include "g1_rules.h"
#include "roz/port/unitree_g1.h"
#include "unitree_hg.h"

typedef unitree_hg_msg_dds__LowCmd_ g1_cmd_t;
typedef unitree_hg_msg_dds__LowState_ g1_state_t;

/* Words the CRC covers: all but the trailing crc. */
#define G1_CMD_CRC_WORDS (sizeof(g1_cmd_t) / 4u - 1u)
#define G1_STATE_CRC_WORDS (sizeof(g1_state_t) / 4u - 1u)


/* LowState_.wireless_remote's bytes as Unitree's SDK lays them out (its
 * remote data union, little-endian): 2 header bytes, the 16-bit key union
 * (R1 bit 0 ... left bit 15), then floats lx, rx, ry, L2, ly, then 16
 * unused bytes. The frame has no analog R2: r2 is its key bit (0 or 1).
 * Returns the number of sticks and triggers that are not finite (they are
 * passed on as they are: the inputs refuse and count each). */
int roz__g1_remote(const uint8_t raw[40], roz_operator_remote_t *out);

/* The manifest joint (index) the robot's hardware variant @p mode_machine
 * has no motor for (23-DoF: slots 13, 14, 20, 21, 27, 28; locked waist: 13,
 * 14), with *why saying so (static, ends "mode_machine" for the code); -1
 * when it has them all (0, simulation, has them all). */
int roz__g1_variant_refuses(const roz_unitree_g1_t *g1, uint32_t mode_machine, const char **why);

/* Whether the frame's CRC matches. */
int roz__g1_state_crc_ok(const g1_state_t *s);

/* The states of the frame into values (n_states, manifest order): positions
 * always, the rest when full. */
void roz__g1_convert(const roz_unitree_g1_t *g1, const g1_state_t *s, double *values, int full);

/* The first joint whose motor reports a fault code, or -1; its code. */
int roz__g1_motor_fault(const roz_unitree_g1_t *g1, const g1_state_t *s, uint32_t *code);

/* The start-up hold as a command frame (n_commands, manifest order): every
 * joint's position command holds q[slot], kd is @p kd where the joint has
 * a damping command, everything else 0; each value clamped to its channel.
 * With @p last (the controller's last command) the stop's hold from it
 * instead (roz_joints_hold_keep()). */
void roz__g1_hold(const roz_unitree_g1_t *g1, const double *q, const double *last, double kd,
                  double *cmd);

/* Fills a zeroed LowCmd_ from a command frame and sets its CRC; a joint
 * without a position command gets @p q[slot] (each slot's last finite
 * measured position, NaN: none: then 0 and no stiffness). */
void roz__g1_fill(const roz_unitree_g1_t *g1, const double *cmd, const double *q,
                  uint8_t mode_machine, g1_cmd_t *out);

/* Fills a zeroed LowCmd_ with the damping command: kp 0 (@p hold: each
 * joint's stiffness default, the hold gain), kd (each joint's damping
 * default when NaN; clamped), q the given positions; and its CRC. */
void roz__g1_fill_damping(const roz_unitree_g1_t *g1, const double *q, double kd, int hold,
                          uint8_t mode_machine, g1_cmd_t *out);

#endif /* ROZ_G1_MAP_H */
