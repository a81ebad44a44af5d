/* SPDX-License-Identifier: Apache-2.0 */
/* A Linux gamepad as the operator's remote (roz/gamepad.h). */
#define _DEFAULT_SOURCE /* ioctl, poll, pipe2 */
#include "roz/gamepad.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

/* the axes read, in roz_gamepad_t's order */
static const uint16_t axis_code[ROZ_GAMEPAD_AXES] = { ABS_X, ABS_Y, ABS_RX, ABS_RY, ABS_Z, ABS_RZ };
enum { AX_LX, AX_LY, AX_RX, AX_RY, AX_L2, AX_R2 };

/* the buttons, by position as on Unitree's remote */
static const struct {
    uint16_t code;
    roz_operator_field_t key;
} buttons[] = {
    { BTN_SOUTH, ROZ_OPERATOR_REMOTE_BTN_A },      { BTN_EAST, ROZ_OPERATOR_REMOTE_BTN_B },
    { BTN_WEST, ROZ_OPERATOR_REMOTE_BTN_X },       { BTN_NORTH, ROZ_OPERATOR_REMOTE_BTN_Y },
    { BTN_TL, ROZ_OPERATOR_REMOTE_BTN_L1 },        { BTN_TR, ROZ_OPERATOR_REMOTE_BTN_R1 },
    { BTN_TL2, ROZ_OPERATOR_REMOTE_BTN_L2 },       { BTN_TR2, ROZ_OPERATOR_REMOTE_BTN_R2 },
    { BTN_SELECT, ROZ_OPERATOR_REMOTE_BTN_SELECT }, { BTN_START, ROZ_OPERATOR_REMOTE_BTN_START },
    { BTN_THUMBL, ROZ_OPERATOR_REMOTE_BTN_F1 },    { BTN_THUMBR, ROZ_OPERATOR_REMOTE_BTN_F2 },
    { BTN_DPAD_UP, ROZ_OPERATOR_REMOTE_BTN_UP },   { BTN_DPAD_DOWN, ROZ_OPERATOR_REMOTE_BTN_DOWN },
    { BTN_DPAD_LEFT, ROZ_OPERATOR_REMOTE_BTN_LEFT }, { BTN_DPAD_RIGHT, ROZ_OPERATOR_REMOTE_BTN_RIGHT },
};
#define N_BUTTONS (sizeof buttons / sizeof buttons[0])

static int present(const struct input_absinfo *a)
{
    return a->maximum > a->minimum;
}

/* A stick: -1..1 about the middle of its range, 0 within the flat. */
static float stick(const roz_gamepad_t *gp, int k)
{
    const struct input_absinfo *a = &gp->abs[k];
    if (!present(a))
        return 0.0f;
    double mid = ((double)a->minimum + (double)a->maximum) / 2.0;
    double half = ((double)a->maximum - (double)a->minimum) / 2.0;
    double d = (double)gp->raw[k] - mid;
    if (d >= -(double)a->flat && d <= (double)a->flat)
        return 0.0f;
    double v = d / half;
    return (float)(v > 1.0 ? 1.0 : v < -1.0 ? -1.0 : v);
}

/* A trigger: 0..1 from the bottom of its range. */
static float trigger(const roz_gamepad_t *gp, int k)
{
    const struct input_absinfo *a = &gp->abs[k];
    if (!present(a))
        return 0.0f;
    double v = ((double)gp->raw[k] - (double)a->minimum) /
               ((double)a->maximum - (double)a->minimum);
    return (float)(v > 1.0 ? 1.0 : v < 0.0 ? 0.0 : v);
}

static uint16_t key(roz_operator_field_t f)
{
    return ROZ_REMOTE_KEY(f);
}

static void build_frame(roz_gamepad_t *gp)
{
    roz_operator_remote_t *r = &gp->frame;
    uint16_t keys = gp->keys;

    r->lx = stick(gp, AX_LX);
    r->ly = -stick(gp, AX_LY);
    r->rx = stick(gp, AX_RX);
    r->ry = -stick(gp, AX_RY);
    r->l2 = trigger(gp, AX_L2);
    r->r2 = trigger(gp, AX_R2);
    if (r->l2 > 0.5f)
        keys |= key(ROZ_OPERATOR_REMOTE_BTN_L2);
    if (r->r2 > 0.5f)
        keys |= key(ROZ_OPERATOR_REMOTE_BTN_R2);
    if (gp->hat_x < 0)
        keys |= key(ROZ_OPERATOR_REMOTE_BTN_LEFT);
    if (gp->hat_x > 0)
        keys |= key(ROZ_OPERATOR_REMOTE_BTN_RIGHT);
    if (gp->hat_y < 0)
        keys |= key(ROZ_OPERATOR_REMOTE_BTN_UP);
    if (gp->hat_y > 0)
        keys |= key(ROZ_OPERATOR_REMOTE_BTN_DOWN);
    r->buttons = keys;
    gp->have_frame = 1;
}

/* Every control released and centred (each axis in the middle of its
 * range; a trigger at its bottom). */
static void neutral(roz_gamepad_t *gp)
{
    for (int k = 0; k < ROZ_GAMEPAD_AXES; k++) {
        const struct input_absinfo *a = &gp->abs[k];
        gp->raw[k] = k >= AX_L2 ? a->minimum
                                : (int32_t)(((int64_t)a->minimum + (int64_t)a->maximum) / 2);
    }
    gp->hat_x = gp->hat_y = 0;
    gp->keys = 0;
}

/* After SYN_DROPPED: the state again from the device, or neutral where it
 * cannot say (a pipe). */
static void resync(roz_gamepad_t *gp)
{
    unsigned long bits[KEY_CNT / (8 * sizeof(unsigned long)) + 1];
    struct input_absinfo a;

    neutral(gp);
    if (gp->fd < 0 || ioctl(gp->fd, EVIOCGKEY(sizeof bits), bits) < 0)
        return;
    for (size_t i = 0; i < N_BUTTONS; i++) {
        unsigned c = buttons[i].code;
        if ((bits[c / (8 * sizeof(unsigned long))] >> (c % (8 * sizeof(unsigned long)))) & 1ul)
            gp->keys |= key(buttons[i].key);
    }
    for (int k = 0; k < ROZ_GAMEPAD_AXES; k++) {
        if (present(&gp->abs[k]) && ioctl(gp->fd, EVIOCGABS(axis_code[k]), &a) == 0)
            gp->raw[k] = a.value;
    }
    if (ioctl(gp->fd, EVIOCGABS(ABS_HAT0X), &a) == 0)
        gp->hat_x = a.value < 0 ? -1 : a.value > 0;
    if (ioctl(gp->fd, EVIOCGABS(ABS_HAT0Y), &a) == 0)
        gp->hat_y = a.value < 0 ? -1 : a.value > 0;
}

void roz_gamepad_init(roz_gamepad_t *gp, const struct input_absinfo abs[ROZ_GAMEPAD_AXES])
{
    memset(gp, 0, sizeof *gp);
    for (int k = 0; k < ROZ_GAMEPAD_AXES; k++)
        gp->abs[k] = abs[k];
    neutral(gp);
    gp->fd = -1;
    gp->wake[0] = gp->wake[1] = -1;
    atomic_init(&gp->frames, 0u);
    atomic_init(&gp->repeats, 0u);
    atomic_init(&gp->drops, 0u);
    atomic_init(&gp->gone, 0);
}

int roz_gamepad_event(roz_gamepad_t *gp, const struct input_event *ev)
{
    if (ev->type == EV_SYN) {
        if (ev->code == SYN_DROPPED) {
            gp->dropped = 1;
            atomic_fetch_add(&gp->drops, 1u);
            return 0;
        }
        if (ev->code != SYN_REPORT)
            return 0;
        if (gp->dropped) {
            gp->dropped = 0;
            resync(gp);
        }
        build_frame(gp);
        return 1;
    }
    if (gp->dropped)
        return 0;
    if (ev->type == EV_KEY) {
        for (size_t i = 0; i < N_BUTTONS; i++) {
            if (buttons[i].code != ev->code)
                continue;
            if (ev->value != 0) /* 1 pressed, 2 autorepeat */
                gp->keys |= key(buttons[i].key);
            else
                gp->keys &= (uint16_t)~key(buttons[i].key);
        }
    } else if (ev->type == EV_ABS) {
        for (int k = 0; k < ROZ_GAMEPAD_AXES; k++) {
            if (axis_code[k] == ev->code)
                gp->raw[k] = ev->value;
        }
        if (ev->code == ABS_HAT0X)
            gp->hat_x = ev->value < 0 ? -1 : ev->value > 0;
        if (ev->code == ABS_HAT0Y)
            gp->hat_y = ev->value < 0 ? -1 : ev->value > 0;
    }
    return 0;
}

static int test_bit(const unsigned long *bits, unsigned c)
{
    return (int)((bits[c / (8 * sizeof(unsigned long))] >> (c % (8 * sizeof(unsigned long)))) & 1ul);
}

int roz_gamepad_open(roz_gamepad_t *gp, const char *path, char *err, size_t errlen)
{
    struct input_absinfo abs[ROZ_GAMEPAD_AXES];
    unsigned long absbits[ABS_CNT / (8 * sizeof(unsigned long)) + 1];
    unsigned long keybits[KEY_CNT / (8 * sizeof(unsigned long)) + 1];
    int fd = open(path, O_RDONLY | O_CLOEXEC);

    if (fd < 0) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    memset(absbits, 0, sizeof absbits);
    memset(keybits, 0, sizeof keybits);
    if (ioctl(fd, EVIOCGBIT(EV_ABS, sizeof absbits), absbits) < 0 ||
        ioctl(fd, EVIOCGBIT(EV_KEY, sizeof keybits), keybits) < 0) {
        snprintf(err, errlen, "%s: not an evdev input device (/dev/input/eventN)", path);
        close(fd);
        return -1;
    }
    if (!test_bit(absbits, ABS_X) && !test_bit(keybits, BTN_SOUTH) &&
        !test_bit(keybits, BTN_GAMEPAD)) {
        snprintf(err, errlen, "%s: neither a stick (ABS_X) nor a gamepad's buttons (BTN_SOUTH)",
                 path);
        close(fd);
        return -1;
    }
    for (int k = 0; k < ROZ_GAMEPAD_AXES; k++) {
        memset(&abs[k], 0, sizeof abs[k]);
        if (test_bit(absbits, axis_code[k]) && ioctl(fd, EVIOCGABS(axis_code[k]), &abs[k]) < 0)
            memset(&abs[k], 0, sizeof abs[k]); /* absent */
    }
    roz_gamepad_open_fd(gp, fd, abs);
    resync(gp); /* what is held now: the first frame, repeated until an event */
    build_frame(gp);
    return 0;
}

void roz_gamepad_open_fd(roz_gamepad_t *gp, int fd, const struct input_absinfo abs[ROZ_GAMEPAD_AXES])
{
    roz_gamepad_init(gp, abs);
    gp->fd = fd;
}

static void hand_on(roz_gamepad_t *gp)
{
    if (gp->sink.remote != NULL)
        (void)gp->sink.remote(gp->sink.ctx, &gp->frame);
}

static void *reader(void *arg)
{
    roz_gamepad_t *gp = arg;
    struct input_event ev[64];

    for (;;) {
        struct pollfd p[2] = { { gp->fd, POLLIN, 0 }, { gp->wake[0], POLLIN, 0 } };
        int n = poll(p, 2, ROZ_GAMEPAD_REPEAT_MS);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 || (p[1].revents & (POLLIN | POLLHUP)) != 0)
            break;
        if (n == 0) { /* quiet: the held controls again, so they do not go stale */
            if (gp->have_frame) {
                hand_on(gp);
                atomic_fetch_add(&gp->repeats, 1u);
            }
            continue;
        }
        ssize_t got = read(gp->fd, ev, sizeof ev);
        if (got < 0 && (errno == EINTR || errno == EAGAIN))
            continue;
        if (got <= 0) { /* unplugged or the end: no more frames, the inputs go stale */
            atomic_store(&gp->gone, got == 0 ? -1 : errno);
            break;
        }
        for (size_t i = 0; i < (size_t)got / sizeof ev[0]; i++) {
            if (roz_gamepad_event(gp, &ev[i]) == 1) {
                hand_on(gp);
                atomic_fetch_add(&gp->frames, 1u);
            }
        }
    }
    return NULL;
}

int roz_gamepad_start(roz_gamepad_t *gp, const roz_operator_sink_t *sink, char *err, size_t errlen)
{
    if (gp->running || gp->fd < 0) {
        snprintf(err, errlen, "gamepad: %s", gp->running ? "already started" : "not open");
        return -1;
    }
    gp->sink = *sink;
    if (pipe(gp->wake) != 0) {
        snprintf(err, errlen, "gamepad: pipe: %s", strerror(errno));
        gp->wake[0] = gp->wake[1] = -1;
        return -1;
    }
    int rc = pthread_create(&gp->thread, NULL, reader, gp);
    if (rc != 0) {
        snprintf(err, errlen, "gamepad: thread: %s", strerror(rc));
        close(gp->wake[0]);
        close(gp->wake[1]);
        gp->wake[0] = gp->wake[1] = -1;
        return -1;
    }
    gp->running = 1;
    return 0;
}

void roz_gamepad_close(roz_gamepad_t *gp)
{
    if (gp->running) {
        close(gp->wake[1]); /* POLLHUP on the other end: the reader leaves */
        gp->wake[1] = -1;
        pthread_join(gp->thread, NULL);
        gp->running = 0;
    }
    if (gp->wake[0] >= 0)
        close(gp->wake[0]);
    if (gp->wake[1] >= 0)
        close(gp->wake[1]);
    gp->wake[0] = gp->wake[1] = -1;
    if (gp->fd >= 0)
        close(gp->fd);
    gp->fd = -1;
}
