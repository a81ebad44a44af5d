/* SPDX-License-Identifier: Apache-2.0 */
/* A recording streamed live (roz/record_live.h): the MCAP of record_file.c
 * through a non-blocking pipe, one tick's chunk queued whole or dropped. */
#define _POSIX_C_SOURCE 200809L
#include "roz/record_live.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define PIECES (ROZ_RECORD_LIVE_QUEUE_TICKS + 2u) /* the ticks, the start, the end */
#define TICK_BIT 0x80000000u

/* The writer's sink: the chunk being made, kept for the queue. */
static int sink(void *ctx, const void *data, size_t n)
{
    roz_record_live_t *l = ctx;
    if (l->one_len + n > l->one_cap) {
        size_t cap = l->one_cap ? l->one_cap : 4096u;
        while (cap < l->one_len + n)
            cap *= 2u;
        if (cap > ROZ_RECORD_LIVE_QUEUE_BYTES)
            return -1; /* no tick is that large; the queue could never take it */
        unsigned char *p = realloc(l->one, cap);
        if (p == NULL)
            return -1;
        l->one = p;
        l->one_cap = cap;
    }
    memcpy(l->one + l->one_len, data, n);
    l->one_len += n;
    return 0;
}

/* Queues l->one whole as one piece; -1 when there is no room. */
static int enqueue(roz_record_live_t *l, int tick)
{
    size_t n = l->one_len;
    if (l->gone || l->ent_n >= PIECES || n > ROZ_RECORD_LIVE_QUEUE_BYTES - (l->q_len - l->q_head))
        return -1;
    if (l->q_len + n > ROZ_RECORD_LIVE_QUEUE_BYTES) { /* room at the front: move up */
        memmove(l->q, l->q + l->q_head, l->q_len - l->q_head);
        l->q_len -= l->q_head;
        l->q_head = 0;
    }
    memcpy(l->q + l->q_len, l->one, n);
    l->q_len += n;
    l->ent[(l->ent_head + l->ent_n) % PIECES] = (uint32_t)n | (tick ? TICK_BIT : 0u);
    l->ent_n++;
    return 0;
}

/* The reader is gone: what is queued will never reach it. */
static void lose(roz_record_live_t *l, const char *what, int err)
{
    if (l->error[0] == '\0')
        snprintf(l->error, sizeof l->error, "%s%s%s", what, err ? ": " : "",
                 err ? strerror(err) : "");
    for (uint32_t i = 0; i < l->ent_n; i++)
        l->dropped += (l->ent[(l->ent_head + i) % PIECES] & TICK_BIT) != 0;
    l->ent_n = 0;
    l->ent_done = 0;
    l->q_head = l->q_len = 0;
    l->gone = 1;
}

int roz_record_live_open(roz_record_live_t *l, const char *path, const roz_runtime_t *rt,
                         roz_recorder_t *rec, const roz_record_file_options_t *opt, char *err,
                         size_t errlen)
{
    struct stat st;
    memset(l, 0, sizeof *l);
    l->path = path;
    l->fd = -1;
    if (strcmp(path, "-") == 0) { /* rozrun's standard output carries its summary */
        snprintf(err, errlen, "-: name a FIFO or a pipe (/dev/fd/N), not standard output");
        return ROZ_EINVAL;
    }
    /* a FIFO or a pipe: its reader must be there (a FIFO's open would
     * otherwise wait for one); anything else is a file, created */
    int fifo = stat(path, &st) == 0 && S_ISFIFO(st.st_mode);
    l->fd = fifo ? open(path, O_WRONLY | O_NONBLOCK | O_CLOEXEC)
                 : open(path, O_WRONLY | O_CREAT | O_TRUNC | O_NONBLOCK | O_CLOEXEC, 0644);
    if (l->fd < 0) {
        int e = errno;
        if (fifo && e == ENXIO)
            snprintf(err, errlen, "%s: nobody reads this FIFO yet: start the viewer on it "
                                  "(roz-live) first", path);
        else
            snprintf(err, errlen, "%s: cannot open: %s", path, strerror(e));
        return ROZ_EIO;
    }
    l->q = malloc(ROZ_RECORD_LIVE_QUEUE_BYTES);
    l->ent = malloc(PIECES * sizeof l->ent[0]);
    if (l->q == NULL || l->ent == NULL) {
        snprintf(err, errlen, "%s: out of memory", path);
        roz_record_live_close(l, 0);
        return ROZ_ENOMEM;
    }
    int rc = roz_record_file_open_stream(&l->f, path, rt, rec, opt, sink, l, err, errlen);
    if (rc != ROZ_OK) {
        close(l->fd);
        l->fd = -1;
        free(l->q);
        free(l->ent);
        free(l->one);
        l->q = l->one = NULL;
        l->ent = NULL;
        return rc;
    }
    (void)enqueue(l, 0); /* the queue is empty: it fits */
    l->one_len = 0;
    roz_record_live_flush(l);
    return ROZ_OK;
}

void roz_record_live_put(roz_record_live_t *l, const roz_record_t *r)
{
    l->ticks++;
    if (l->gone) {
        l->dropped++;
        return;
    }
    l->one_len = 0;
    if (roz_record_file_put(&l->f, r) != ROZ_OK) {
        lose(l, "cannot encode a tick", 0);
        l->dropped++;
        return;
    }
    if (enqueue(l, 1) != 0) {
        l->dropped++;
        /* the controller's name went with it: say it again in the next one */
        l->f.have_hash = 0;
    }
    l->one_len = 0;
}

void roz_record_live_flush(roz_record_live_t *l)
{
    while (!l->gone && l->ent_n > 0) {
        ssize_t w = write(l->fd, l->q + l->q_head, l->q_len - l->q_head);
        if (w < 0 && errno == EINTR)
            continue;
        if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return; /* the pipe is full: the rest waits for the next flush */
        if (w < 0) {
            lose(l, errno == EPIPE ? "the viewer went away" : "write failed",
                 errno == EPIPE ? 0 : errno);
            return;
        }
        l->q_head += (size_t)w;
        l->ent_done += (size_t)w;
        while (l->ent_n > 0) {
            uint32_t e = l->ent[l->ent_head];
            size_t len = e & ~TICK_BIT;
            if (l->ent_done < len)
                break;
            l->ent_done -= len;
            l->sent += (e & TICK_BIT) != 0;
            l->ent_head = (l->ent_head + 1u) % PIECES;
            l->ent_n--;
        }
        if (l->q_head == l->q_len)
            l->q_head = l->q_len = 0;
    }
}

static uint64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

void roz_record_live_close(roz_record_live_t *l, unsigned wait_ms)
{
    if (l->fd < 0)
        return;
    if (l->q != NULL && l->ent != NULL) {
        l->one_len = 0;
        if (roz_mcap_close(&l->f.w) == ROZ_OK && !l->gone)
            (void)enqueue(l, 0); /* no room: the stream ends without its footer */
        uint64_t until = now_ms() + wait_ms;
        roz_record_live_flush(l);
        while (!l->gone && l->ent_n > 0) {
            uint64_t t = now_ms();
            if (t >= until)
                break;
            struct pollfd p = { l->fd, POLLOUT, 0 };
            (void)poll(&p, 1, (int)(until - t));
            roz_record_live_flush(l);
        }
        if (l->ent_n > 0)
            lose(l, "the viewer was still behind at the end", 0);
    } else {
        (void)roz_mcap_close(&l->f.w);
    }
    close(l->fd);
    l->fd = -1;
    free(l->f.msg);
    l->f.msg = NULL;
    free(l->q);
    free(l->ent);
    free(l->one);
    l->q = l->one = NULL;
    l->ent = NULL;
}

uint64_t roz_record_live_ticks(const roz_record_live_t *l)
{
    return l->ticks;
}

uint64_t roz_record_live_sent(const roz_record_live_t *l)
{
    return l->sent;
}

uint64_t roz_record_live_dropped(const roz_record_live_t *l)
{
    return l->dropped;
}

const char *roz_record_live_error(const roz_record_live_t *l)
{
    return l->error;
}
