/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun --teleop SOCKET (teleop.h). */
#define _POSIX_C_SOURCE 200809L
#include "teleop.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include "roz/error.h"
#include "roz/joy.h"

static double le_f64(const unsigned char *p)
{
    uint64_t b = 0;
    double v;
    for (int i = 7; i >= 0; i--)
        b = b << 8 | p[i];
    memcpy(&v, &b, sizeof v);
    return v;
}

static uint32_t le_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* The map a datagram carries (@p len bytes at @p text, not empty): the
 * last one's, read again only when the text changed; NULL when the rule
 * refuses it (said on stderr once per text). */
static const roz_joy_map_t *sent_map(rozrun_teleop_t *t, const unsigned char *text, size_t len)
{
    char err[ROZRUN_TELEOP_JOY_MAP_MAX + 256];
    if (len == t->sent_len && memcmp(text, t->sent_text, len) == 0)
        return t->sent_ok ? &t->sent_map : NULL;
    memcpy(t->sent_text, text, len);
    t->sent_text[len] = '\0';
    t->sent_len = len;
    t->sent_ok = memchr(text, '\0', len) == NULL &&
                 roz_joy_map_parse("roz-live --joy-map", t->sent_text, &t->sent_map, err,
                                   sizeof err) == ROZ_OK;
    if (!t->sent_ok)
        fprintf(stderr, "rozrun: --teleop %s: %s; its Joys are refused\n", t->path,
                memchr(text, '\0', len) != NULL ? "a Joy's map holds a NUL byte" : err);
    return t->sent_ok ? &t->sent_map : NULL;
}

/* A "JOY1" datagram of @p n bytes through its map (or the panel's) to the
 * remote; 0 taken, -1 refused (its shape, or the map's rule). */
static int take_joy(rozrun_teleop_t *t, const unsigned char *buf, size_t n)
{
    float axes[ROZRUN_TELEOP_JOY_MAX];
    int32_t buttons[ROZRUN_TELEOP_JOY_MAX];
    unsigned na = buf[4], nb = buf[5];
    size_t ml = (size_t)buf[6] | (size_t)buf[7] << 8;
    if (na > ROZRUN_TELEOP_JOY_MAX || nb > ROZRUN_TELEOP_JOY_MAX ||
        ml > ROZRUN_TELEOP_JOY_MAP_MAX || n != 8u + 4u * (na + nb) + ml)
        return -1;
    const roz_joy_map_t *map = ml == 0 ? &t->joy_map : sent_map(t, buf + n - ml, ml);
    if (map == NULL)
        return -1;
    for (unsigned k = 0; k < na; k++) {
        uint32_t u = le_u32(buf + 8 + 4 * k);
        memcpy(&axes[k], &u, sizeof u);
    }
    for (unsigned k = 0; k < nb; k++)
        buttons[k] = (int32_t)le_u32(buf + 8 + 4 * (na + k));
    roz_operator_remote_t r;
    if (roz_joy_remote(map, axes, na, buttons, nb, &r) != ROZ_OK)
        return -1;
    (void)roz_runtime_operator_remote(t->rt, &r);
    return 0;
}

static void *teleop_main(void *arg)
{
    rozrun_teleop_t *t = arg;
    /* one byte more than the largest: a longer datagram is seen as such */
    unsigned char buf[ROZRUN_TELEOP_JOY_BYTES_MAX + 1];
    while (!atomic_load(&t->stop)) {
        ssize_t n = recv(t->fd, buf, sizeof buf, 0);
        if (n < 0)
            continue; /* the 100 ms timeout, or a signal: look at stop again */
        if (n >= 8 && memcmp(buf, "JOY1", 4) == 0) {
            if (take_joy(t, buf, (size_t)n) == 0)
                atomic_fetch_add(&t->joys, 1u);
            else
                atomic_fetch_add(&t->refused, 1u);
            continue;
        }
        if (n != ROZRUN_TELEOP_TWIST_BYTES || memcmp(buf, "TWST", 4) != 0) {
            atomic_fetch_add(&t->refused, 1u);
            continue;
        }
        roz_operator_twist_t tw;
        for (int k = 0; k < 3; k++) {
            tw.linear[k] = le_f64(buf + 4 + 8 * k);
            tw.angular[k] = le_f64(buf + 28 + 8 * k);
        }
        (void)roz_runtime_operator_twist(t->rt, &tw);
        atomic_fetch_add(&t->twists, 1u);
    }
    return NULL;
}

int rozrun_teleop_open(rozrun_teleop_t *t, const char *path)
{
    struct sockaddr_un a;
    struct stat st;
    memset(t, 0, sizeof *t);
    t->path = path;
    t->fd = -1;
    atomic_init(&t->stop, 0);
    atomic_init(&t->twists, 0u);
    atomic_init(&t->joys, 0u);
    atomic_init(&t->refused, 0u);
    char err[256];
    if (roz_joy_map_parse("the Joystick panel's map", ROZRUN_TELEOP_JOY_MAP, &t->joy_map, err,
                          sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: --teleop: %s\n", err); /* a bug */
        return -1;
    }
    if (strlen(path) >= sizeof a.sun_path) {
        fprintf(stderr, "rozrun: --teleop %s: longer than a socket's path may be (%zu)\n", path,
                sizeof a.sun_path - 1);
        return -1;
    }
    if (lstat(path, &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            fprintf(stderr, "rozrun: --teleop %s: exists and is not a socket\n", path);
            return -1;
        }
        (void)unlink(path); /* an earlier run's */
    }
    t->fd = socket(AF_UNIX, SOCK_DGRAM, 0);
    if (t->fd < 0) {
        fprintf(stderr, "rozrun: --teleop %s: socket: %s\n", path, strerror(errno));
        return -1;
    }
    memset(&a, 0, sizeof a);
    a.sun_family = AF_UNIX;
    memcpy(a.sun_path, path, strlen(path) + 1);
    mode_t old = umask(0177); /* 0600: this user only */
    int rc = bind(t->fd, (struct sockaddr *)&a, sizeof a);
    (void)umask(old);
    struct timeval tv = { 0, 100000 };
    if (rc != 0 || setsockopt(t->fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv) != 0) {
        fprintf(stderr, "rozrun: --teleop %s: %s\n", path, strerror(errno));
        close(t->fd);
        t->fd = -1;
        return -1;
    }
    return 0;
}

int rozrun_teleop_start(rozrun_teleop_t *t, roz_runtime_t *rt)
{
    pthread_t th;
    t->rt = rt;
    if (pthread_create(&th, NULL, teleop_main, t) != 0) {
        fprintf(stderr, "rozrun: --teleop %s: cannot start its thread\n", t->path);
        return -1;
    }
    t->thread = (unsigned long)th;
    t->running = 1;
    return 0;
}

void rozrun_teleop_close(rozrun_teleop_t *t)
{
    if (t->path == NULL)
        return; /* never opened */
    if (t->running) {
        atomic_store(&t->stop, 1);
        (void)pthread_join((pthread_t)t->thread, NULL);
        t->running = 0;
    }
    if (t->fd >= 0) {
        close(t->fd);
        (void)unlink(t->path);
        t->fd = -1;
    }
}
