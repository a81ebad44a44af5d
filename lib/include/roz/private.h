/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/private.h
 * @brief Private fields in roz's public structs.
 *
 * roz's structs are allocated by the application (static storage, no heap),
 * so their complete types are in the public headers. Their fields are not an
 * interface: each is declared `ROZ_PRIVATE(name)`, which roz's own sources
 * see as `name` and everyone else as `roz_private_name_`, so code that
 * reaches into a struct does not compile by accident and stands out when it
 * does it on purpose. Read what a struct holds through roz's functions
 * (their `Context:` lines say from which thread). White-box tests define
 * ROZ_PRIVATE_ACCESS before including roz's headers.
 */
#ifndef ROZ_PRIVATE_H
#define ROZ_PRIVATE_H

#ifdef ROZ_PRIVATE_ACCESS
#define ROZ_PRIVATE(name) name
#else
#define ROZ_PRIVATE(name) roz_private_##name##_
#endif

#endif /* ROZ_PRIVATE_H */
