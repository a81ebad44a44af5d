/* SPDX-License-Identifier: Apache-2.0 */
/* What test_port_vectors uses: a robot.toml loaded by
 * roz's C loader and opened through the DDS port its [hardware] names
 * (unitree/G1, agibot/X2, engineai/PM01; and mujoco where the test defines
 * ROZ_TEST_HAVE_MUJOCO), constructed from the registry (roz/ports.h) with
 * no run-time parameter, as rozrun would; closed again when it opens. */
#ifndef ROZ_TEST_DDS_OPEN_FILE_H
#define ROZ_TEST_DDS_OPEN_FILE_H

#include <stddef.h>

/** The loader refused the file (@p err: its first problem). */
#define ROZ_TEST_NOT_LOADED (-1000)
/** The file's robot is not on a DDS port. */
#define ROZ_TEST_NO_DDS_PORT (-1001)

/**
 * @brief Load @p file and open its DDS port.
 * @param[out] port_name the [hardware] port named ("" when none); may be NULL
 * @return ROZ_OK (opened and closed), the port's error code (@p err: its
 *         message), ROZ_TEST_NOT_LOADED or ROZ_TEST_NO_DDS_PORT
 * Context: one thread (static storage).
 */
int roz_test_dds_open_file(const char *file, const char **port_name, char *err, size_t errlen);

#endif /* ROZ_TEST_DDS_OPEN_FILE_H */
