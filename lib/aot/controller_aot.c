/* SPDX-License-Identifier: Apache-2.0 */
/* The ahead-of-time engine behind roz/controller.h (roz/aot.h): the
 * runtime that C written by wasm2c (Debian's wabt) needs, over static
 * storage, and roz's imports under the names wasm2c calls them by. The
 * imports are roz/abi.h's, charged as the wasm3 engine charges them
 * (controller.c), and the fuel runs through the same meter
 * (controller_meter.h). This library exports wasm2c's names (wasm_rt_*,
 * Z_<module>Z_<name>), which is why it is not part of roz::core. */
#include "roz/aot.h"

#include <setjmp.h>
#include <stdarg.h>
#include <string.h>

#include "roz/format.h"

#include "roz/aot_generated.h"
#include "controller_meter.h"

/* wasm2c's names for the value types, as its generated headers define them */
#ifndef WASM_RT_CORE_TYPES_DEFINED
#define WASM_RT_CORE_TYPES_DEFINED
typedef uint32_t u32;
typedef uint64_t u64;
typedef double   f64;
#endif

/* ---- private: the call in progress on this thread ------------------------ */

typedef struct {
    jmp_buf           jmp;
    roz_controller_t *c;
} aot_call_t;

static ROZ_AOT_THREAD_LOCAL aot_call_t *current;
static ROZ_AOT_THREAD_LOCAL const char *current_trap;
ROZ_AOT_THREAD_LOCAL uint32_t roz__aot_depth;
/* declared by wasm-rt.h; the generated code counts in roz__aot_depth */
#undef wasm_rt_call_stack_depth
uint32_t wasm_rt_call_stack_depth;

/* the trap texts are wasm3's, so a fault reads the same on both engines */
static const char *trap_text(wasm_rt_trap_t code)
{
    switch (code) {
    case WASM_RT_TRAP_OOB: return "[trap] out of bounds memory access";
    case WASM_RT_TRAP_INT_OVERFLOW: return "[trap] integer overflow";
    case WASM_RT_TRAP_DIV_BY_ZERO: return "[trap] integer divide by zero";
    case WASM_RT_TRAP_INVALID_CONVERSION: return "[trap] invalid conversion to integer";
    case WASM_RT_TRAP_UNREACHABLE: return "[trap] unreachable executed";
    case WASM_RT_TRAP_CALL_INDIRECT:
        return "[trap] indirect call: undefined element or type mismatch";
    case WASM_RT_TRAP_EXHAUSTION: return "[trap] stack overflow";
    default: return "[trap] unknown";
    }
}

static _Noreturn void trap_with(const char *why)
{
    current_trap = why;
    longjmp(current->jmp, 1);
}

void wasm_rt_trap(wasm_rt_trap_t code)
{
    trap_with(trap_text(code));
}

/* ---- private: start-up state (one load at a time) ------------------------- */

/* Function types by their signature letters ("iF:i"), in a pool;
 * call_indirect compares the index this returns, so equal signatures must
 * get equal indices. The registry holds the types of the controllers
 * loaded (each registers its own at every load) and is emptied when none
 * is, so it never fills up over swaps. */
#define TYPE_POOL_BYTES (ROZ_CFG_AOT_MAX_TYPES * 24u)
#define SIG_MAX         1100u /* 1000 parameters, as WebAssembly engines allow, and more */
static struct {
    uint16_t at, len;
} types[ROZ_CFG_AOT_MAX_TYPES];
static char     type_pool[TYPE_POOL_BYTES];
static uint32_t n_types, pool_used;
static int      types_full;
static unsigned live; /* instances loaded, every compiled controller */

/* the storage of the instance being started */
static uint8_t           *arena_memory;
static uint32_t           arena_pages;
static wasm_rt_funcref_t *arena_table;
static uint32_t           arena_table_n;
static int                arena_short;

static char type_letter(wasm_rt_type_t t)
{
    switch (t) {
    case WASM_RT_I32: return 'i';
    case WASM_RT_I64: return 'I';
    case WASM_RT_F32: return 'f';
    case WASM_RT_F64: return 'F';
    default: return 'r';
    }
}

uint32_t wasm_rt_register_func_type(uint32_t params, uint32_t results, ...)
{
    char sig[SIG_MAX];
    size_t n = 0;
    va_list ap;
    va_start(ap, results);
    for (uint32_t i = 0; i < params + results; i++) {
        char l = type_letter((wasm_rt_type_t)va_arg(ap, int)); /* promoted */
        if (i == params && n < SIG_MAX)
            sig[n++] = ':';
        if (n < SIG_MAX)
            sig[n++] = l;
    }
    va_end(ap);
    if (results == 0 && n < SIG_MAX)
        sig[n++] = ':';
    for (uint32_t i = 0; i < n_types; i++)
        if (types[i].len == n && memcmp(type_pool + types[i].at, sig, n) == 0)
            return i + 1;
    if (n >= SIG_MAX || n_types >= ROZ_CFG_AOT_MAX_TYPES || pool_used + n > TYPE_POOL_BYTES) {
        types_full = 1;
        return 0xffffffffu - n_types; /* never equal to a registered one; the load fails */
    }
    memcpy(type_pool + pool_used, sig, n);
    types[n_types].at = (uint16_t)pool_used;
    types[n_types].len = (uint16_t)n;
    pool_used += (uint32_t)n;
    return ++n_types;
}

bool wasm_rt_is_initialized(void)
{
    return true;
}

/* A memory or table larger than the build gave the controller stops the
 * start there, before any data segment is written: the compiled bounds
 * checks take the memory's size as its declaration gives it
 * (cmake/RozAotBound.cmake). */
void wasm_rt_allocate_memory(wasm_rt_memory_t *mem, uint32_t initial_pages, uint32_t max_pages)
{
    (void)max_pages;
    if (initial_pages > arena_pages || (initial_pages != 0 && arena_memory == NULL)) {
        arena_short = 1;
        mem->data = NULL;
        mem->pages = mem->max_pages = 0;
        mem->size = 0;
        wasm_rt_trap(WASM_RT_TRAP_OOB);
    }
    mem->data = arena_memory;
    mem->pages = initial_pages;
    mem->max_pages = initial_pages; /* fixed: growing would allocate in the tick */
    mem->size = initial_pages * 65536u;
    if (mem->size != 0)
        memset(mem->data, 0, mem->size);
}

uint32_t wasm_rt_grow_memory(wasm_rt_memory_t *mem, uint32_t delta)
{
    return delta == 0 ? mem->pages : 0xffffffffu;
}

void wasm_rt_free_memory(wasm_rt_memory_t *mem)
{
    mem->data = NULL;
    mem->size = 0;
    mem->pages = 0;
}

void wasm_rt_allocate_funcref_table(wasm_rt_funcref_table_t *t, uint32_t elements,
                                    uint32_t max_elements)
{
    (void)max_elements;
    if (elements > arena_table_n) {
        arena_short = 1;
        t->data = NULL;
        t->size = t->max_size = 0;
        wasm_rt_trap(WASM_RT_TRAP_OOB);
    }
    t->data = arena_table;
    t->size = elements;
    t->max_size = elements;
    for (uint32_t i = 0; i < elements; i++)
        t->data[i] = wasm_rt_funcref_null_value;
}

void wasm_rt_free_funcref_table(wasm_rt_funcref_table_t *t)
{
    t->data = NULL;
    t->size = 0;
}

/* ---- private: the imports --------------------------------------------------- */

/* Every import module's instance pointer is the controller (rozaot's glue
 * passes it for each). */
#define CTL(p) ((roz_controller_t *)(void *)(p))
#define ABI(p) (CTL(p)->abi)

static int64_t *fuel_of(roz_controller_t *c)
{
    return c->aot_fuel;
}

static void charge(roz_controller_t *c, uint64_t units)
{
    const char *trap = roz__controller_charge(c, fuel_of(c), units);
    if (trap != NULL)
        trap_with(trap);
}

static uint8_t *memory(roz_controller_t *c, size_t *len)
{
    const wasm_rt_memory_t *mem = c->aot_memory;
    *len = mem != NULL ? mem->size : 0u;
    return mem != NULL ? mem->data : NULL;
}

struct Z_command_instance_t;
struct Z_state_instance_t;
struct Z_math_instance_t;
struct Z_safety_instance_t;
struct Z_timing_instance_t;
struct Z_telemetry_instance_t;
struct Z_nn_instance_t;
struct Z_roz_instance_t;

/* declared here as the generated headers declare them */
u32 Z_commandZ_set(struct Z_command_instance_t *p, u32 index, f64 value);
u32 Z_commandZ_count(struct Z_command_instance_t *p);
f64 Z_commandZ_limit_min(struct Z_command_instance_t *p, u32 index);
f64 Z_commandZ_limit_max(struct Z_command_instance_t *p, u32 index);
u32 Z_commandZ_set_all(struct Z_command_instance_t *p, u32 ptr, u32 count);
f64 Z_stateZ_get(struct Z_state_instance_t *p, u32 index);
u32 Z_stateZ_count(struct Z_state_instance_t *p);
u32 Z_stateZ_get_all(struct Z_state_instance_t *p, u32 ptr, u32 count);
f64 Z_mathZ_sin(struct Z_math_instance_t *p, f64 x);
f64 Z_mathZ_cos(struct Z_math_instance_t *p, f64 x);
void Z_safetyZ_request_estop(struct Z_safety_instance_t *p);
u64 Z_timingZ_now_ns(struct Z_timing_instance_t *p);
u64 Z_timingZ_sim_time_ns(struct Z_timing_instance_t *p);
void Z_telemetryZ_emit_metric(struct Z_telemetry_instance_t *p, f64 value);
u32 Z_nnZ_matvec(struct Z_nn_instance_t *p, u32 w, u32 x, u32 b, u32 y, u32 rows, u32 cols,
                 u32 flags);
u32 Z_nnZ_act(struct Z_nn_instance_t *p, u32 kind, u32 ptr, u32 count);
void Z_rozZ_refuel(struct Z_roz_instance_t *p);
void Z_rozZ_fill(struct Z_roz_instance_t *p, u32 d, u32 n);
void Z_rozZ_copy(struct Z_roz_instance_t *p, u32 d, u32 s, u32 n);

u32 Z_commandZ_set(struct Z_command_instance_t *p, u32 index, f64 value)
{
    return (u32)roz_abi_command_set(ABI(p), (int32_t)index, value);
}

u32 Z_commandZ_count(struct Z_command_instance_t *p)
{
    return (u32)roz_abi_command_count(ABI(p));
}

f64 Z_commandZ_limit_min(struct Z_command_instance_t *p, u32 index)
{
    return roz_abi_command_limit_min(ABI(p), (int32_t)index);
}

f64 Z_commandZ_limit_max(struct Z_command_instance_t *p, u32 index)
{
    return roz_abi_command_limit_max(ABI(p), (int32_t)index);
}

/* an import a build left out (roz/config.h) is not defined here: a
 * compiled controller importing it does not link */
#if ROZ_CFG_BULK_IMPORTS
u32 Z_commandZ_set_all(struct Z_command_instance_t *p, u32 ptr, u32 count)
{
    size_t len;
    charge(CTL(p), roz_abi_command_set_all_units((int32_t)count));
    const uint8_t *mem = memory(CTL(p), &len);
    return (u32)roz_abi_command_set_all(ABI(p), mem, len, ptr, (int32_t)count);
}
#endif

f64 Z_stateZ_get(struct Z_state_instance_t *p, u32 index)
{
    return roz_abi_state_get(ABI(p), (int32_t)index);
}

u32 Z_stateZ_count(struct Z_state_instance_t *p)
{
    return (u32)roz_abi_state_count(ABI(p));
}

#if ROZ_CFG_BULK_IMPORTS
u32 Z_stateZ_get_all(struct Z_state_instance_t *p, u32 ptr, u32 count)
{
    size_t len;
    charge(CTL(p), roz_abi_state_get_all_units((int32_t)count));
    uint8_t *mem = memory(CTL(p), &len);
    return (u32)roz_abi_state_get_all(ABI(p), mem, len, ptr, (int32_t)count);
}
#endif

#if ROZ_CFG_MATH_IMPORTS
f64 Z_mathZ_sin(struct Z_math_instance_t *p, f64 x)
{
    charge(CTL(p), roz_abi_math_units(x));
    return roz_abi_math_sin(x);
}

f64 Z_mathZ_cos(struct Z_math_instance_t *p, f64 x)
{
    charge(CTL(p), roz_abi_math_units(x));
    return roz_abi_math_cos(x);
}
#endif

void Z_safetyZ_request_estop(struct Z_safety_instance_t *p)
{
    roz_abi_safety_request_estop(ABI(p));
}

u64 Z_timingZ_now_ns(struct Z_timing_instance_t *p)
{
    charge(CTL(p), ROZ_ABI_NOW_UNITS);
    return (u64)roz_abi_timing_now_ns(ABI(p));
}

u64 Z_timingZ_sim_time_ns(struct Z_timing_instance_t *p)
{
    return (u64)roz_abi_timing_sim_time_ns(ABI(p));
}

void Z_telemetryZ_emit_metric(struct Z_telemetry_instance_t *p, f64 value)
{
    roz_abi_telemetry_emit_metric(ABI(p), value);
}

#if ROZ_CFG_NN_IMPORTS
u32 Z_nnZ_matvec(struct Z_nn_instance_t *p, u32 w, u32 x, u32 b, u32 y, u32 rows, u32 cols,
                 u32 flags)
{
    size_t len;
    charge(CTL(p), roz_abi_nn_matvec_units((int32_t)rows, (int32_t)cols));
    uint8_t *mem = memory(CTL(p), &len);
    return (u32)roz_abi_nn_matvec(ABI(p), mem, len, w, x, b, y, (int32_t)rows, (int32_t)cols,
                                  (int32_t)flags);
}

u32 Z_nnZ_act(struct Z_nn_instance_t *p, u32 kind, u32 ptr, u32 count)
{
    size_t len;
    charge(CTL(p), roz_abi_nn_act_units((int32_t)kind, (int32_t)count));
    uint8_t *mem = memory(CTL(p), &len);
    return (u32)roz_abi_nn_act(ABI(p), mem, len, (int32_t)kind, ptr, (int32_t)count);
}
#endif

/* The metering rozaot inserted: a charge took the fuel global below zero. */
void Z_rozZ_refuel(struct Z_roz_instance_t *p)
{
    const char *trap = roz__controller_refuel(CTL(p), fuel_of(CTL(p)));
    if (trap != NULL)
        trap_with(trap);
}

/* memory.fill and memory.copy pay for their bytes once their bounds hold,
 * before they run (out of bounds, the op itself traps, as in wasm3);
 * d_m3RozBytesPerUnit (16) bytes a unit */
#define BULK_BYTES_PER_UNIT 16u

void Z_rozZ_fill(struct Z_roz_instance_t *p, u32 d, u32 n)
{
    size_t len;
    (void)memory(CTL(p), &len);
    if ((uint64_t)d + n <= len)
        charge(CTL(p), n / BULK_BYTES_PER_UNIT);
}

void Z_rozZ_copy(struct Z_roz_instance_t *p, u32 d, u32 s, u32 n)
{
    size_t len;
    (void)memory(CTL(p), &len);
    if ((uint64_t)d + n <= len && (uint64_t)s + n <= len)
        charge(CTL(p), n / BULK_BYTES_PER_UNIT);
}

/* ---- private: the engine's call and unload -------------------------------- */

static const char *aot_call(roz_controller_t *c, int64_t tick, int64_t slice, int64_t **fuel_out)
{
    const roz_aot_module_t *m = c->aot_module;
    aot_call_t call;
    aot_call_t *outer = current;
    uint32_t depth = roz__aot_depth;
    int64_t *fuel = c->aot_fuel;

    *fuel_out = fuel;
    *fuel = slice;
    call.c = c;
    current = &call;
    current_trap = NULL;
    if (setjmp(call.jmp) == 0)
        m->process(c->aot_slot, tick);
    roz__aot_depth = depth;
    current = outer;
    return current_trap;
}

static void aot_unload(roz_controller_t *c)
{
    const roz_aot_module_t *m = c->aot_module;
    if (m != NULL) {
        m->release(c->aot_slot);
        m->in_use[c->aot_slot] = 0;
        live--;
    }
    c->aot_module = NULL;
}

/* ---- public -------------------------------------------------------------- */

static volatile int loading; /* one load at a time: the start-up state above */

int roz_controller_load_aot(roz_controller_t *c, const roz_aot_module_t *m, roz_abi_t *abi)
{
    unsigned slot;
    aot_call_t call;
    aot_call_t *outer = current;

    if (roz_controller_loaded(c))
        return ROZ_ESTATE;
    c->error[0] = '\0';
    c->calls = 0;
    if (abi == NULL || m == NULL) {
        roz_format(c->error, sizeof c->error, "no ABI context or module");
        return ROZ_EINVAL;
    }
    if (__atomic_exchange_n(&loading, 1, __ATOMIC_ACQUIRE) != 0) {
        roz_format(c->error, sizeof c->error, "%s: another compiled controller is loading",
                   m->name);
        return ROZ_ESTATE;
    }
    for (slot = 0; slot < m->instances && m->in_use[slot]; slot++) {
    }
    if (slot == m->instances) {
        __atomic_store_n(&loading, 0, __ATOMIC_RELEASE);
        roz_format(c->error, sizeof c->error,
                   "%s: all %u instances in use (ROZ_CFG_AOT_INSTANCES)", m->name, m->instances);
        return ROZ_ENOMEM;
    }
    if (live == 0) {
        n_types = 0; /* no compiled controller holds an index into it */
        pool_used = 0;
    }
    types_full = 0;
    m->init_module();
    arena_memory = m->memory != NULL ? m->memory + (size_t)slot * m->pages * 65536u : NULL;
    arena_pages = m->pages;
    arena_table = m->tables != NULL ? (wasm_rt_funcref_t *)m->tables + (size_t)slot * m->table
                                    : NULL;
    arena_table_n = m->table;
    arena_short = 0;
    c->abi = abi;
    c->aot_module = m;
    c->aot_slot = slot;
    c->unmetered = 0;
    call.c = c;
    current = &call;
    current_trap = NULL;
    if (setjmp(call.jmp) == 0)
        m->instantiate(slot, c); /* data and element segments (checked by the validator) */
    current = outer;
    m->in_use[slot] = 1;
    live++;
    int bad_types = types_full;
    __atomic_store_n(&loading, 0, __ATOMIC_RELEASE);
    if (current_trap != NULL || arena_short || bad_types) {
        roz_format(c->error, sizeof c->error, "%s: %s", m->name,
                   bad_types      ? "more function types than ROZ_CFG_AOT_MAX_TYPES"
                   : arena_short ? "its memory or table is larger than the build gave it"
                                  : current_trap);
        aot_unload(c);
        c->abi = NULL;
        return ROZ_EINVAL;
    }
    c->aot_fuel = m->fuel(slot);
    c->aot_memory = m->memory_of(slot);
    c->engine_call = aot_call;
    c->engine_unload = aot_unload;
    c->process = (void *)(uintptr_t)m; /* loaded */
    return ROZ_OK;
}
