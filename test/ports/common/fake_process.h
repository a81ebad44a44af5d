/* SPDX-License-Identifier: Apache-2.0 */
/* A fake robot as a separate process, driven over its stdin/stdout: one
 * request line in, one reply line out ("ok ..." or "err ..."); it prints
 * "ready" once it can be asked, exits on "quit" or the end of its stdin.
 * What fake_g1_client.c and fake_ros2_client.c share. */
#ifndef ROZ_TEST_FAKE_PROCESS_H
#define ROZ_TEST_FAKE_PROCESS_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <sys/types.h>

typedef struct roz_fake_process {
    pid_t pid;         /* 0: not running */
    FILE *to;          /* its stdin */
    FILE *from;        /* its stdout */
    char  line[16384]; /* the last reply */
} roz_fake_process_t;

/* Starts @p path with @p args (argv after argv[0], NULL-terminated) and
 * waits for its "ready". 0, or -1 with err said, naming @p what ("fake_g1
 * on domain 15"). */
int roz_fake_process_start(roz_fake_process_t *f, const char *path, const char *const *args,
                           const char *what, char *err, size_t errlen);

/* One request; 0 when the reply is "ok ...", 1 when "err ...", -1 when the
 * process is gone. The reply is in f->line. */
int roz_fake_process_vask(roz_fake_process_t *f, const char *fmt, va_list ap)
    __attribute__((format(printf, 2, 0)));

/* One request that must be answered "ok ...": anything else fails the
 * running cmocka test, naming @p who ("fake_g1"), the request and the
 * reply. */
void roz_fake_process_vmust(roz_fake_process_t *f, const char *who, const char *fmt, va_list ap)
    __attribute__((format(printf, 3, 0)));

/* "quit", then its exit status (-1: it did not exit cleanly; a process that
 * does not exit within 10 s is killed). */
int roz_fake_process_stop(roz_fake_process_t *f);

/* Sleep @p ms milliseconds. */
void roz_fake_sleep_ms(unsigned ms);

#endif /* ROZ_TEST_FAKE_PROCESS_H */
