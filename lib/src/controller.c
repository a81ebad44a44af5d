/* SPDX-License-Identifier: Apache-2.0 */
/* The wasm3 engine behind roz/controller.h. This is the only file of roz
 * that includes wasm3's headers; it reaches into m3_env.h (pinned wasm3
 * 0.5.0) for one thing the public API lacks: capping linear memory at its
 * initial size. */
#include "roz/controller.h"

#include <string.h>

#include "roz/format.h"
#include "roz/text.h"

#include "wasm3.h"
#include "m3_env.h"
#include "controller_bench.h"
#include "controller_meter.h"
#include "wasm_scan.h"

/* ---- private: metering ----------------------------------------------------- */

/* roz's patch (cmake/wasm3/02-metering.patch) makes wasm3 charge every run
 * of straight-line code, and every byte of memory.fill/memory.copy, against
 * M3Runtime.rozFuel before it runs, and compare the C stack at every wasm
 * call and loop entry with the lowest the call has reached. The fuel is
 * handed out in slices: a charge that takes the slice below zero lands in
 * roz__wasm3_refuel(), which stops the call once the budget is spent, reads
 * the clock for the deadline, and hands out the next slice. With a deadline
 * a slice is ROZ_CFG_DEADLINE_CHECK_UNITS, so the clock is read after at
 * most that much work plus one charge (a run of at most d_m3RozMaxRun
 * instructions, or one bulk memory op, bounded by the memory's size). The
 * state lives in the controller, which the runtime's userdata points at. */

const char roz__controller_fuel_trap[] = "[trap] fuel exhausted";
const char roz__controller_deadline_trap[] = "[trap] deadline passed";
static const char stack_trap[] = "[trap] native stack limit";
#define fuel_trap     roz__controller_fuel_trap
#define deadline_trap roz__controller_deadline_trap

/* A slice no charge can reach below zero when nothing is metered. */
#define UNMETERED_SLICE ((uint64_t)1 << 62)

/* The current C stack position: the frame address where the compiler gives
 * it (never a sanitizer's fake stack), else a local's address. */
#if defined(__GNUC__) || defined(__clang__)
#define STACK_HERE() ((uintptr_t)__builtin_frame_address(0))
#else
#define STACK_HERE() stack_here_fallback()
static uintptr_t stack_here_fallback(void)
{
    volatile char here = 0;
    return (uintptr_t)&here;
}
#endif

/* The next slice: what is left of the budget, at most one deadline
 * interval when a deadline is set. */
static uint64_t next_slice(const roz_controller_t *c)
{
    uint64_t left = c->budget.fuel == ROZ_BUDGET_OFF ? UNMETERED_SLICE
                                                     : c->budget.fuel - c->meter_used;
    if (c->meter_deadline != 0 && left > ROZ_CFG_DEADLINE_CHECK_UNITS)
        left = ROZ_CFG_DEADLINE_CHECK_UNITS;
    return left < UNMETERED_SLICE ? left : UNMETERED_SLICE;
}

/* Engine-neutral (controller_meter.h): every engine keeps the slice's fuel
 * in an int64_t of its own (wasm3: M3Runtime.rozFuel; the AOT engine: a
 * global of the metered module) and calls this when a charge took it below
 * zero. */
const char *roz__controller_refuel(roz_controller_t *c, int64_t *fuel)
{
    /* all charged so far, the charge that emptied the slice included */
    uint64_t used = c->meter_used + c->meter_slice + (uint64_t)(-*fuel);

    c->meter_used = used;
    c->meter_slice = 0;
    *fuel = 0;
    if (c->budget.fuel != ROZ_BUDGET_OFF && used > c->budget.fuel)
        return fuel_trap;
    if (c->meter_deadline != 0 && c->budget.clock(c->budget.clock_ctx) > c->meter_deadline)
        return deadline_trap;
    c->meter_slice = next_slice(c);
    *fuel = (int64_t)c->meter_slice;
    return NULL;
}

const char *roz__controller_charge(roz_controller_t *c, int64_t *fuel, uint64_t units)
{
    if (c->unmetered)
        return NULL;
    *fuel -= (int64_t)units;
    return *fuel < 0 ? roz__controller_refuel(c, fuel) : NULL;
}

M3Result roz__wasm3_refuel(IM3Runtime rt)
{
    return roz__controller_refuel(rt->userdata, &rt->rozFuel);
}

M3Result roz__wasm3_stack(IM3Runtime rt, void *here)
{
    roz_controller_t *c = rt->userdata;
    size_t depth = c->stack_base - (uintptr_t)here; /* stacks grow down */

    rt->rozStackLow = here;
    c->stack_used = depth;
    return depth > ROZ_CFG_NATIVE_STACK_BYTES ? stack_trap : m3Err_none;
}

/* ---- private: the imports as wasm3 raw functions -------------------------- */

#define ABI ((roz_abi_t *)_ctx->userdata)

static m3ApiRawFunction(h_command_set)
{
    m3ApiReturnType(int32_t);
    m3ApiGetArg(int32_t, index);
    m3ApiGetArg(double, value);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_command_set(ABI, index, value));
}

static m3ApiRawFunction(h_command_count)
{
    m3ApiReturnType(int32_t);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_command_count(ABI));
}

static m3ApiRawFunction(h_command_limit_min)
{
    m3ApiReturnType(double);
    m3ApiGetArg(int32_t, index);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_command_limit_min(ABI, index));
}

static m3ApiRawFunction(h_command_limit_max)
{
    m3ApiReturnType(double);
    m3ApiGetArg(int32_t, index);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_command_limit_max(ABI, index));
}

static m3ApiRawFunction(h_state_get)
{
    m3ApiReturnType(double);
    m3ApiGetArg(int32_t, index);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_state_get(ABI, index));
}

static m3ApiRawFunction(h_state_count)
{
    m3ApiReturnType(int32_t);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_state_count(ABI));
}

/* Charges `units` against the running call's fuel, as the metering patch's
 * op_roz_Charge does; a non-NULL result is the trap. */
static M3Result charge(IM3Runtime rt, uint64_t units)
{
    return roz__controller_charge(rt->userdata, &rt->rozFuel, units);
}

/* In a host function: charge `units` before any work, and trap when the
 * fuel is out. */
#define CHARGE_OR_TRAP(units)                        \
    do {                                             \
        M3Result charge_r_ = charge(runtime, units); \
        if (charge_r_ != m3Err_none)                 \
            m3ApiTrap(charge_r_);                    \
    } while (0)

#if ROZ_CFG_MATH_IMPORTS
static m3ApiRawFunction(h_math_sin)
{
    m3ApiReturnType(double);
    m3ApiGetArg(double, x);
    (void)_mem;
    (void)_ctx;
    CHARGE_OR_TRAP(roz_abi_math_units(x));
    m3ApiReturn(roz_abi_math_sin(x));
}

static m3ApiRawFunction(h_math_cos)
{
    m3ApiReturnType(double);
    m3ApiGetArg(double, x);
    (void)_mem;
    (void)_ctx;
    CHARGE_OR_TRAP(roz_abi_math_units(x));
    m3ApiReturn(roz_abi_math_cos(x));
}
#else
#define h_math_sin NULL /* left out: as h_nn_matvec */
#define h_math_cos NULL
#endif

static m3ApiRawFunction(h_safety_request_estop)
{
    (void)runtime;
    (void)_mem;
    (void)_sp;
    roz_abi_safety_request_estop(ABI);
    m3ApiSuccess();
}

static m3ApiRawFunction(h_timing_now_ns)
{
    m3ApiReturnType(int64_t);
    (void)_mem;
    CHARGE_OR_TRAP(ROZ_ABI_NOW_UNITS);
    m3ApiReturn(roz_abi_timing_now_ns(ABI));
}

static m3ApiRawFunction(h_timing_sim_time_ns)
{
    m3ApiReturnType(int64_t);
    (void)runtime;
    (void)_mem;
    m3ApiReturn(roz_abi_timing_sim_time_ns(ABI));
}

static m3ApiRawFunction(h_telemetry_emit_metric)
{
    m3ApiGetArg(double, value);
    (void)runtime;
    (void)_mem;
    roz_abi_telemetry_emit_metric(ABI, value);
    m3ApiSuccess();
}

#if ROZ_CFG_BULK_IMPORTS
static m3ApiRawFunction(h_state_get_all)
{
    m3ApiReturnType(int32_t);
    m3ApiGetArg(uint32_t, ptr);
    m3ApiGetArg(int32_t, count);
    uint32_t len = 0;
    uint8_t *mem;
    (void)_mem;
    CHARGE_OR_TRAP(roz_abi_state_get_all_units(count));
    mem = m3_GetMemory(runtime, &len, 0);
    m3ApiReturn(roz_abi_state_get_all(ABI, mem, len, ptr, count));
}

static m3ApiRawFunction(h_command_set_all)
{
    m3ApiReturnType(int32_t);
    m3ApiGetArg(uint32_t, ptr);
    m3ApiGetArg(int32_t, count);
    uint32_t len = 0;
    const uint8_t *mem;
    (void)_mem;
    CHARGE_OR_TRAP(roz_abi_command_set_all_units(count));
    mem = m3_GetMemory(runtime, &len, 0);
    m3ApiReturn(roz_abi_command_set_all(ABI, mem, len, ptr, count));
}
#else
#define h_state_get_all   NULL /* left out: as h_nn_matvec */
#define h_command_set_all NULL
#endif

#if ROZ_CFG_NN_IMPORTS
/* The neural-network extension: its work (multiply-adds, activation
 * elements; roz/abi.h has the units) is charged from the counts before
 * anything is read, so a budget stops a flood of large calls. */
static m3ApiRawFunction(h_nn_matvec)
{
    m3ApiReturnType(int32_t);
    m3ApiGetArg(uint32_t, w);
    m3ApiGetArg(uint32_t, x);
    m3ApiGetArg(uint32_t, b);
    m3ApiGetArg(uint32_t, y);
    m3ApiGetArg(int32_t, rows);
    m3ApiGetArg(int32_t, cols);
    m3ApiGetArg(int32_t, flags);
    uint32_t len = 0;
    uint8_t *mem;
    (void)_mem;
    CHARGE_OR_TRAP(roz_abi_nn_matvec_units(rows, cols));
    mem = m3_GetMemory(runtime, &len, 0);
    m3ApiReturn(roz_abi_nn_matvec(ABI, mem, len, w, x, b, y, rows, cols, flags));
}

static m3ApiRawFunction(h_nn_act)
{
    m3ApiReturnType(int32_t);
    m3ApiGetArg(int32_t, kind);
    m3ApiGetArg(uint32_t, ptr);
    m3ApiGetArg(int32_t, count);
    uint32_t len = 0;
    uint8_t *mem;
    (void)_mem;
    CHARGE_OR_TRAP(roz_abi_nn_act_units(kind, count));
    mem = m3_GetMemory(runtime, &len, 0);
    m3ApiReturn(roz_abi_nn_act(ABI, mem, len, kind, ptr, count));
}
#else
/* left out of the build: refused at load (wasm_scan.c), never linked */
#define h_nn_matvec NULL
#define h_nn_act    NULL
#endif

/* Same order as roz_abi_imports[] (checked at load). */
static const M3RawCall host_functions[] = {
    h_command_set,       h_command_count,   h_command_limit_min,  h_command_limit_max,
    h_state_get,         h_state_count,     h_math_sin,           h_math_cos,
    h_safety_request_estop, h_timing_now_ns, h_timing_sim_time_ns, h_telemetry_emit_metric,
    h_state_get_all,     h_command_set_all, h_nn_matvec,          h_nn_act,
};

/* The engine's two entries (roz_controller_t.engine_call, engine_unload):
 * process(tick) on the slice's fuel, and freeing the runtime. */
static const char *wasm3_call(roz_controller_t *c, int64_t tick, int64_t slice, int64_t **fuel)
{
    IM3Runtime rt = c->runtime;

    rt->rozFuel = slice;
    rt->rozStackLow = (void *)c->stack_base;
    M3Result r = m3_CallV((IM3Function)c->process, tick);
    *fuel = &rt->rozFuel;
    return r;
}

static void wasm3_unload(roz_controller_t *c)
{
    if (c->runtime != NULL)
        m3_FreeRuntime((IM3Runtime)c->runtime);
    if (c->env != NULL)
        m3_FreeEnvironment((IM3Environment)c->env);
    c->env = NULL;
}

/* wasm3 writes signatures as ret(args) with F for f64, I for i64, i for i32,
 * v for none: the roz/abi.h notation, so the table's strings pass through. */

static int fail(roz_controller_t *c, int rc, const char *what, const char *detail)
{
    roz_format(c->error, sizeof c->error, "%s%s%s", what, detail ? ": " : "", detail ? detail : "");
    roz_controller_unload(c);
    return rc;
}

/* ---- public -------------------------------------------------------------- */

void roz_controller_init(roz_controller_t *c)
{
    memset(c, 0, sizeof *c);
    c->budget.fuel = ROZ_BUDGET_OFF;
    c->budget.deadline_ns = ROZ_BUDGET_OFF;
}

int roz_controller_loaded(const roz_controller_t *c)
{
    return c->process != NULL;
}

const char *roz_controller_error(const roz_controller_t *c)
{
    return c->error;
}

/* The validator with its scratch on this frame's stack: a call of its own,
 * so that the scratch is gone before the engine compiles (which recurses,
 * docs/budget.md: the loader's C stack), and the two never add up. */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((noinline))
#endif
static int scan_on_stack(const uint8_t *wasm, size_t len, uint32_t *process_index, char *why,
                         size_t whylen)
{
    roz_load_scratch_t scratch;
    return roz__wasm_scan(wasm, len, &scratch, process_index, why, whylen);
}

/* The loader; `metered` 0 compiles no fuel charges (benchmarks only, see
 * controller_bench.h): such an instance accepts no budget but "off".
 * `scratch` NULL: the validator's scratch on the stack. */
static int load(roz_controller_t *c, const uint8_t *wasm, size_t len, roz_abi_t *abi, int metered,
                roz_load_scratch_t *scratch)
{
    int scanned;
    IM3Environment env;
    IM3Runtime rt;
    IM3Module mod = NULL;
    IM3Function fn = NULL;
    M3Result r;
    uint32_t process_index = 0;
    char why[ROZ_CFG_ERROR_LEN];

    _Static_assert(sizeof host_functions / sizeof host_functions[0] == 16,
                   "one host function per roz_abi_imports[] entry");
    if (c->engine_call != NULL || c->engine_unload != NULL)
        return ROZ_ESTATE;
    c->error[0] = '\0';
    c->calls = 0;
    if (abi == NULL)
        return fail(c, ROZ_EINVAL, "no ABI context", NULL);
    if (len > ROZ_CFG_WASM_MAX_MODULE_BYTES) {
        roz_format(why, sizeof why, "%zu bytes, more than ROZ_CFG_WASM_MAX_MODULE_BYTES (%u)", len,
                   (unsigned)ROZ_CFG_WASM_MAX_MODULE_BYTES);
        return fail(c, ROZ_EINVAL, "module too large", why);
    }
    scanned = scratch != NULL
                  ? roz__wasm_scan(wasm, len, scratch, &process_index, why, sizeof why)
                  : scan_on_stack(wasm, len, &process_index, why, sizeof why);
    if (scanned != ROZ_OK)
        return fail(c, ROZ_EINVAL, why, NULL);

    env = m3_NewEnvironment();
    if (env == NULL)
        return fail(c, ROZ_ENOMEM, "out of memory creating the engine", NULL);
    c->env = env;
    c->engine_unload = wasm3_unload;
    /* the metering hooks find the controller through the runtime */
    rt = m3_NewRuntime(env, ROZ_CFG_WASM_STACK_BYTES, c);
    if (rt == NULL)
        return fail(c, ROZ_ENOMEM, "out of memory creating the runtime", NULL);
    c->runtime = rt;

    r = m3_ParseModule(env, &mod, wasm, (uint32_t)len);
    if (r != m3Err_none)
        return fail(c, ROZ_EINVAL, "malformed module", r);
    if (mod->memoryInfo.initPages > ROZ_CFG_WASM_MAX_PAGES) {
        /* the message first: freeing the module frees memoryInfo too */
        /* most often the stack a linker reserved, not data: rustc's default
         * is 1 MiB (docs/rust.md, test_rust_controller) */
        roz_format(why, sizeof why,
                   "%u pages of 64 KiB, more than ROZ_CFG_WASM_MAX_PAGES (%u); if it is "
                   "the stack, link with -z stack-size=16384",
                   (unsigned)mod->memoryInfo.initPages, (unsigned)ROZ_CFG_WASM_MAX_PAGES);
        m3_FreeModule(mod);
        return fail(c, ROZ_EINVAL, "linear memory too large", why);
    }
    r = m3_LoadModule(rt, mod);
    if (r != m3Err_none) {
        m3_FreeModule(mod);
        return fail(c, ROZ_EINVAL, "cannot load module", r);
    }
    c->module = mod; /* owned by the runtime from here on */
    /* Fixed memory: growing would allocate inside the tick. */
    rt->memory.maxPages = rt->memory.numPages;

    for (size_t i = 0; i < roz_abi_import_count; i++) {
        const roz_abi_import_t *imp = &roz_abi_imports[i];
        if (host_functions[i] == NULL)
            continue; /* left out: the scan refused a module importing it */
        r = m3_LinkRawFunctionEx(mod, imp->module, imp->name, imp->signature, host_functions[i],
                                 abi);
        if (r != m3Err_none && r != m3Err_functionLookupFailed) {
            roz_format(why, sizeof why, "%s.%s: %s", imp->module, imp->name, r);
            return fail(c, ROZ_EINVAL, "cannot link import", why);
        }
    }
    rt->rozUnmetered = metered ? 0 : 1;
    c->unmetered = !metered;
    r = m3_CompileModule(mod);
    if (r != m3Err_none)
        return fail(c, ROZ_EINVAL, "cannot compile module", r);
    /* Names (SAFETY.md §3, test_names): nothing roz runs is found by a name wasm3
     * resolves on its own.
     *  - process is called as the function index roz__wasm_scan checked,
     *    never through m3_FindFunction (which returns the first function
     *    with the name, from any export or the name section). The export's
     *    names are unique, UTF-8 and NUL-free (wasm_scan.c); the name
     *    section, like every custom section, is never parsed by wasm3
     *    (cmake/wasm3/30-custom-sections.patch). m3_FindFunction also
     *    compiles the function (m3_CompileModule above compiled them all)
     *    and runs a start function (roz refuses those: checked again here).
     *  - imports are linked by m3_LinkRawFunctionEx, which compares wasm3's
     *    NUL-ended copies of module and field names with strcmp. roz checked
     *    every import byte for byte against roz_abi_imports[] and refused
     *    names with a NUL byte, so strcmp sees the same bytes: each import
     *    links to exactly the host function whose signature roz checked.
     *  - no other lookup by name (m3_FindGlobal, m3_GetFunctionName) is
     *    used. */
    if (process_index < mod->numFuncImports || process_index >= mod->numFunctions ||
        mod->startFunction >= 0)
        return fail(c, ROZ_EINVAL, "cannot find process", "engine disagrees with the scan");
    fn = &mod->functions[process_index];
    if (fn->compiled == NULL || fn->module != mod || mod->runtime != rt ||
        fn->funcType == NULL || fn->funcType->numArgs != 1 || fn->funcType->numRets != 0 ||
        d_FuncArgType(fn->funcType, 0) != c_m3Type_i64)
        return fail(c, ROZ_EINVAL, "cannot find process",
                    "the engine's function is not the compiled process(i64) roz checked");
    c->abi = abi;
    c->process = fn;
    c->engine_call = wasm3_call;
    return ROZ_OK;
}

int roz_controller_load(roz_controller_t *c, const uint8_t *wasm, size_t len, roz_abi_t *abi)
{
    return load(c, wasm, len, abi, 1, NULL);
}

int roz_controller_load_in(roz_controller_t *c, const uint8_t *wasm, size_t len, roz_abi_t *abi,
                           roz_load_scratch_t *scratch)
{
    return load(c, wasm, len, abi, 1, scratch);
}

int roz__controller_load_unmetered(roz_controller_t *c, const uint8_t *wasm, size_t len,
                                   roz_abi_t *abi)
{
    return load(c, wasm, len, abi, 0, NULL);
}

int roz_controller_set_budget(roz_controller_t *c, const roz_budget_t *budget)
{
    /* 0 is a budget that allows nothing, never a silent "unmetered"; an
     * instance compiled without charges cannot keep any budget */
    if (budget->fuel == 0 || budget->deadline_ns == 0 ||
        (budget->deadline_ns != ROZ_BUDGET_OFF && budget->clock == NULL) ||
        (c->unmetered && (budget->fuel != ROZ_BUDGET_OFF || budget->deadline_ns != ROZ_BUDGET_OFF)))
        return ROZ_EINVAL;
    c->budget = *budget;
    return ROZ_OK;
}

uint64_t roz_controller_fuel_used(const roz_controller_t *c)
{
    return c->fuel_used;
}

size_t roz_controller_stack_used(const roz_controller_t *c)
{
    return c->stack_used;
}

int roz_controller_process(roz_controller_t *c, int64_t tick)
{
    uint64_t start_ns = 0;

    if (c->process != NULL && !c->spent && c->budget.deadline_ns != ROZ_BUDGET_OFF)
        start_ns = c->budget.clock(c->budget.clock_ctx);
    return roz_controller_process_from(c, tick, start_ns);
}

int roz_controller_process_from(roz_controller_t *c, int64_t tick, uint64_t start_ns)
{
    const char *r;

    if (c->process == NULL || c->spent)
        return ROZ_ESTATE;
    c->calls++;
    c->meter_used = 0;
    c->meter_deadline = 0;
    if (c->budget.deadline_ns != ROZ_BUDGET_OFF)
        c->meter_deadline = start_ns + c->budget.deadline_ns;
    c->meter_slice = next_slice(c);
    c->stack_base = STACK_HERE();
    c->stack_used = 0;
    int64_t *fuel = NULL;
    r = c->engine_call(c, tick, (int64_t)c->meter_slice, &fuel);
    c->fuel_used = c->meter_used + (c->meter_slice - (uint64_t)*fuel);
    /* Messages built without printf: this runs in the tick. A budget stop
     * leaves the instance spent; after a trap the caller decides (the
     * runtime never runs a trapped instance again). */
    if (r == NULL)
        return ROZ_OK;
    roz_text_t t;
    roz_text_init(&t, c->error, sizeof c->error);
    if (r == fuel_trap || r == deadline_trap) {
        c->spent = 1;
        roz_text_put(&t, r == fuel_trap ? "fuel exhausted at tick " : "deadline passed at tick ");
        roz_text_put_i64(&t, tick);
        if (r == fuel_trap) {
            roz_text_put(&t, ": ");
            roz_text_put_u64(&t, c->fuel_used);
            roz_text_put(&t, " units, budget ");
            roz_text_put_u64(&t, c->budget.fuel);
        } else {
            roz_text_put(&t, ": ");
            roz_text_put_u64(&t, c->budget.deadline_ns / 1000u);
            roz_text_put(&t, " us budget, stopped after ");
            roz_text_put_u64(&t, c->fuel_used);
            roz_text_put(&t, " units");
        }
        return ROZ_ETIMEDOUT;
    }
    roz_text_put(&t, "trap at tick ");
    roz_text_put_i64(&t, tick);
    if (r == stack_trap) {
        roz_text_put(&t, ": native stack limit: ");
        roz_text_put_u64(&t, c->stack_used);
        roz_text_put(&t, " bytes deep, limit ");
        roz_text_put_u64(&t, ROZ_CFG_NATIVE_STACK_BYTES);
        roz_text_put(&t, " (ROZ_CFG_NATIVE_STACK_BYTES)");
    } else {
        roz_text_put(&t, ": ");
        roz_text_put(&t, r);
    }
    return ROZ_ETRAP;
}

int roz_controller_spent(const roz_controller_t *c)
{
    return c->spent;
}

uint64_t roz_controller_calls(const roz_controller_t *c)
{
    return c->calls;
}

void roz_controller_unload(roz_controller_t *c)
{
    if (c->engine_unload != NULL)
        c->engine_unload(c);
    c->runtime = NULL;
    c->env = NULL;
    c->module = NULL;
    c->process = NULL;
    c->abi = NULL;
    c->spent = 0;
    c->engine_call = NULL;
    c->engine_unload = NULL;
}
