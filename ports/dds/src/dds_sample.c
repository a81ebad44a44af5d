/* SPDX-License-Identifier: Apache-2.0 */
/* Samples with sequences and strings (ROS 2 messages): their buffers sized
 * once at open with Cyclone's allocator, so its deserializer fills them in
 * place and may grow or free them. */
#include "dds_internal.h"

#include <string.h>

/* The sequence owns its buffer (_release): Cyclone 0.10's deserializer
 * grows a releasing sequence that is too short, but fills a sequence of
 * structs that does not release past its _maximum (it reads every element
 * the sample carries), which a hostile sample would turn into an overflow
 * of the port's storage. */
int roz_dds_seq_reserve(void *seq, uint32_t n, size_t elem_size)
{
    dds_sequence_t *s = seq;

    if (s == NULL || n == 0 || elem_size == 0 || s->_buffer != NULL ||
        elem_size > UINT32_MAX / n)
        return ROZ_EINVAL;
    s->_buffer = dds_alloc((size_t)n * elem_size);
    if (s->_buffer == NULL)
        return ROZ_ENOSPC;
    memset(s->_buffer, 0, (size_t)n * elem_size);
    s->_maximum = n;
    s->_length = 0;
    s->_release = true;
    return ROZ_OK;
}

int roz_dds_string_reserve(char **s, size_t len)
{
    if (s == NULL || *s != NULL || len == 0 || len > 65535u)
        return ROZ_EINVAL;
    char *b = dds_alloc(len + 1u);
    if (b == NULL)
        return ROZ_ENOSPC;
    /* Cyclone reuses the buffer for a string no longer than the one in it */
    memset(b, '-', len);
    b[len] = '\0';
    *s = b;
    return ROZ_OK;
}

void roz_dds_sample_free(void *sample, size_t size, const void *descriptor)
{
    if (sample == NULL || descriptor == NULL)
        return;
    dds_sample_free(sample, descriptor, DDS_FREE_CONTENTS);
    memset(sample, 0, size);
}
