/* SPDX-License-Identifier: Apache-2.0 */
/* ROS time: the system clock as a builtin_interfaces/Time, and a header
 * stamp as the sequence number the link checks take. */
#define _POSIX_C_SOURCE 200809L
#include "roz/port/ros2.h"

#include <time.h>

void roz_ros2_stamp_now(int32_t *sec, uint32_t *nanosec)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_REALTIME, &ts);
    *sec = (int32_t)ts.tv_sec;
    *nanosec = (uint32_t)ts.tv_nsec;
}

int roz_ros2_stamp_seq(int32_t sec, uint32_t nanosec, uint32_t *seq)
{
    if (sec < 0 || nanosec > 999999999u) {
        *seq = 0;
        return 0;
    }
    /* microseconds modulo 2^32 (71 minutes): consecutive stamps of a live
     * robot are milliseconds apart, far inside half the range */
    uint64_t us = (uint64_t)(uint32_t)sec * 1000000u + nanosec / 1000u;
    *seq = (uint32_t)us;
    return 1;
}
