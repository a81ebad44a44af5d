/* SPDX-License-Identifier: Apache-2.0 */
/* A reader of the parts of an MJCF model (MuJoCo's XML) the mujoco port
 * binds a manifest to, without MuJoCo (mjcf_scan.c). Private to the mujoco
 * port: its rules library (the checker rozgen runs) reads the model with
 * it, and its open reads the include tree with it, within the same limits,
 * before MuJoCo reads the model. */
#ifndef ROZ_MUJOCO_MJCF_SCAN_H
#define ROZ_MUJOCO_MJCF_SCAN_H

#include <stddef.h>

/* includes followed at most this deep (a file including itself stops
 * here), includes in all, and bytes of XML in all (the model and every
 * include): a few files including each other many times would otherwise
 * make billions of elements */
#define ROZ_MJCF_MAX_DEPTH    16
#define ROZ_MJCF_MAX_INCLUDES 256
#define ROZ_MJCF_MAX_BYTES    (32 * 1024 * 1024)
#define ROZ_MJCF_PATH_MAX     1024

/* A joint of the model (the first of its name). */
typedef struct roz__mjcf_joint {
    const char *name;
    const char *type;     /* hinge, slide, ball, free */
    int         limited;  /* actuatorfrcrange applies */
    double      range[2]; /* actuatorfrcrange */
} roz__mjcf_joint_t;

/* An actuator (every element of <actuator>, in model order). */
typedef struct roz__mjcf_actuator {
    const char *name;     /* NULL: none */
    const char *joint;    /* "" when it drives no joint */
    double      gear;     /* the first of gear */
    int         limited;  /* forcerange applies */
    double      range[2]; /* forcerange */
} roz__mjcf_actuator_t;

/* A sensor (every element of <sensor>). */
typedef struct roz__mjcf_sensor {
    const char *name; /* NULL: none */
    const char *type; /* the element: gyro, accelerometer, ... */
    const char *site; /* NULL: none */
} roz__mjcf_sensor_t;

typedef struct roz__mjcf_doc roz__mjcf_doc_t;

/* The model: <include file=...> followed, <default> classes applied as
 * MuJoCo applies them (an element's class, else its body's childclass,
 * else main; a class inherits from the classes around it). */
typedef struct roz__mjcf_model {
    roz__mjcf_joint_t    *joints;
    size_t                n_joints;
    roz__mjcf_actuator_t *actuators;
    size_t                n_actuators;
    roz__mjcf_sensor_t   *sensors;
    size_t                n_sensors;
    roz__mjcf_doc_t      *doc; /* the files' text the names point into */
} roz__mjcf_model_t;

/* Reads the model at @p path: ROZ_OK; else ROZ_EINVAL (ROZ_ENOMEM) and the
 * reason, naming the file or the chain of includes, in @p err. Free with
 * roz__mjcf_free() either way. Allocates (start-up and host tools only). */
int roz__mjcf_read(const char *path, roz__mjcf_model_t *out, char *err, size_t errlen);
void roz__mjcf_free(roz__mjcf_model_t *m);

#endif /* ROZ_MUJOCO_MJCF_SCAN_H */
