/* SPDX-License-Identifier: Apache-2.0 */
/* The receive path: a data-available listener takes each sample into the
 * port's preallocated storage and hands it to the port, on Cyclone's
 * receive thread. */
#include "dds_internal.h"

#include <string.h>

#include "roz/hal/clock.h"

/* Takes what arrived, a bounded number of samples (the next call takes the
 * rest). */
static void take_all(roz_dds_reader_t *r, dds_entity_t reader)
{
    for (uint32_t k = 0; k < ROZ_DDS_TAKE_MAX; k++) {
        void *samples[1] = { r->sample };
        dds_sample_info_t info[1];

        /* zeroed before every take: Cyclone writes the members, never the
         * padding between them, and a CRC over the native struct covers
         * the padding as zeros; kept storage holds the buffers its
         * sequences and strings were given at open */
        if (!r->keep)
            memset(r->sample, 0, r->sample_size);
        dds_return_t n = dds_take(reader, samples, info, 1, 1);
        if (n < 0) {
            atomic_fetch_add_explicit(&r->take_errors, 1u, memory_order_relaxed);
            return;
        }
        if (n == 0)
            return;
        if (!info[0].valid_data) {
            atomic_fetch_add_explicit(&r->invalid, 1u, memory_order_relaxed);
            continue;
        }
        uint64_t t0 = roz_clock_monotonic_ns(NULL);
        r->fn(r->ctx, r->sample, t0);
        atomic_fetch_add_explicit(&r->samples, 1u, memory_order_relaxed);
        if (r->monitor != NULL) {
            uint64_t t1 = roz_clock_monotonic_ns(NULL);
            roz_monitor_record(r->monitor, ROZ_MON_STATE_HANDLER, t1 - t0, t1);
        }
    }
}

/* One call takes at a time, so the storage has one user: a call that finds
 * another taking leaves the work to it (pending tells it to look again). */
static void on_data_available(dds_entity_t reader, void *arg)
{
    roz_dds_reader_t *r = arg;

    if (!atomic_load_explicit(&r->armed, memory_order_acquire))
        return;
    atomic_fetch_add_explicit(&r->pending, 1u, memory_order_seq_cst);
    while (atomic_exchange_explicit(&r->busy, 1u, memory_order_acquire) == 0u) {
        uint32_t seen = atomic_load_explicit(&r->pending, memory_order_seq_cst);
        take_all(r, reader);
        atomic_store_explicit(&r->busy, 0u, memory_order_release);
        /* another call came while this one took: it left its work here
         * unless it gets busy itself, which the exchange above decides */
        if (atomic_load_explicit(&r->pending, memory_order_seq_cst) == seen)
            break;
    }
    atomic_fetch_add_explicit(&r->calls, 1u, memory_order_release);
}

static int reader_open(roz_dds_reader_t *r, const roz_dds_participant_t *p, const char *topic,
                       const void *descriptor, const roz_dds_qos_t *qos, void *storage,
                       size_t size, int keep, roz_dds_sample_fn fn, void *ctx,
                       roz_monitor_t *monitor, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    atomic_init(&r->armed, 0u);
    atomic_init(&r->busy, 0u);
    atomic_init(&r->pending, 0u);
    atomic_init(&r->calls, 0u);
    atomic_init(&r->samples, 0u);
    atomic_init(&r->invalid, 0u);
    atomic_init(&r->take_errors, 0u);
    if (p == NULL || p->participant <= 0 || topic == NULL || descriptor == NULL || qos == NULL ||
        storage == NULL || size == 0 || fn == NULL) {
        roz__dds_say(err, errlen, topic != NULL ? topic : "?", "reader", DDS_RETCODE_BAD_PARAMETER);
        return ROZ_EINVAL;
    }
    r->sample = storage;
    r->sample_size = size;
    r->keep = keep;
    r->fn = fn;
    r->ctx = ctx;
    r->monitor = monitor;

    dds_entity_t t = dds_create_topic(p->participant, descriptor, topic, NULL, NULL);
    if (t < 0) {
        roz__dds_say(err, errlen, topic, "no topic", t);
        return roz__dds_error(t);
    }
    r->topic = t;
    dds_qos_t *q = roz__dds_qos(qos);
    dds_listener_t *l = dds_create_listener(r);
    if (q == NULL || l == NULL) {
        dds_delete_qos(q);
        dds_delete_listener(l);
        roz__dds_say(err, errlen, topic, "reader", DDS_RETCODE_OUT_OF_RESOURCES);
        roz_dds_reader_close(r);
        return ROZ_ENOSPC;
    }
    dds_lset_data_available(l, on_data_available);
    atomic_store_explicit(&r->armed, 1u, memory_order_release);
    dds_entity_t rd = dds_create_reader(p->participant, t, q, l);
    dds_delete_qos(q);
    dds_delete_listener(l);
    if (rd < 0) {
        roz__dds_say(err, errlen, topic, "no reader", rd);
        roz_dds_reader_close(r);
        return roz__dds_error(rd);
    }
    r->reader = rd;
    return ROZ_OK;
}

int roz_dds_reader_open(roz_dds_reader_t *r, const roz_dds_participant_t *p, const char *topic,
                        const void *descriptor, const roz_dds_qos_t *qos, void *storage,
                        size_t size, roz_dds_sample_fn fn, void *ctx, roz_monitor_t *monitor,
                        char *err, size_t errlen)
{
    return reader_open(r, p, topic, descriptor, qos, storage, size, 0, fn, ctx, monitor, err,
                       errlen);
}

int roz_dds_reader_open_kept(roz_dds_reader_t *r, const roz_dds_participant_t *p,
                             const char *topic, const void *descriptor, const roz_dds_qos_t *qos,
                             void *storage, size_t size, roz_dds_sample_fn fn, void *ctx,
                             roz_monitor_t *monitor, char *err, size_t errlen)
{
    return reader_open(r, p, topic, descriptor, qos, storage, size, 1, fn, ctx, monitor, err,
                       errlen);
}

uint32_t roz_dds_reader_matched(const roz_dds_reader_t *r)
{
    dds_subscription_matched_status_t st;
    if (r->reader <= 0 || dds_get_subscription_matched_status(r->reader, &st) != DDS_RETCODE_OK)
        return 0;
    return st.current_count;
}

void roz_dds_reader_close(roz_dds_reader_t *r)
{
    /* dds_delete waits for a listener call in progress to return; the
     * load makes the last call's work happen before the caller's next */
    if (r->reader > 0)
        (void)dds_delete(r->reader);
    (void)atomic_load_explicit(&r->calls, memory_order_acquire);
    if (r->topic > 0)
        (void)dds_delete(r->topic);
    r->reader = 0;
    r->topic = 0;
}
