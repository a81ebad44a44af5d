// SPDX-License-Identifier: Apache-2.0
// roz from C++: every public header in one C++ translation unit, and the
// runtime driven through them on the loopback port (a UR5, the smallest
// controller, 100 ticks). check_cxx.cmake compiles each header alone in
// C++11, 14, 17 and 20 as well, and builds and runs this program.
#include <cstdio>

#include "roz/abi.h"
#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/builtin.h"
#include "roz/config.h"
#include "roz/controller.h"
#include "roz/error.h"
#include "roz/filter.h"
#include "roz/hal/clock.h"
#include "roz/hal/crc32.h"
#include "roz/hal/link.h"
#include "roz/module.h"
#include "roz/hal/params.h"
#include "roz/port.h"
#include "roz/runner.h"
#include "roz/log.h"
#include "roz/port/loopback.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/runtime.h"

namespace {

// (module (func (export "process") (param i64)))
const uint8_t idle_wasm[] = {
    0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, 0x01, 0x05, 0x01, 0x60, 0x01,
    0x7e, 0x00, 0x03, 0x02, 0x01, 0x00, 0x07, 0x0b, 0x01, 0x07, 0x70, 0x72, 0x6f,
    0x63, 0x65, 0x73, 0x73, 0x00, 0x00, 0x0a, 0x04, 0x01, 0x02, 0x00, 0x0b,
};

roz_runtime_t rt;
roz_loopback_t lb;

int fail(const char *what)
{
    std::fprintf(stderr, "cxx consumer: %s\n", what);
    return 1;
}

} // namespace

int main()
{
    const roz_manifest_t *m = roz_builtin_find("ur5");
    if (m == nullptr)
        return fail("no ur5");
    roz_runtime_config_t cfg;
    char err[128];
    roz_port_t port = roz_loopback_port(&lb, NULL, NULL);
    if (roz_port_open(&port, m, nullptr, err, sizeof err) != ROZ_OK)
        return fail(err);
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK)
        return fail("init");
    if (roz_runtime_load(&rt, idle_wasm, sizeof idle_wasm, nullptr) != ROZ_OK)
        return fail(roz_runtime_error(&rt));
    if (roz_runtime_start(&rt) != ROZ_OK)
        return fail("start");
    for (int t = 0; t < 100; t++) {
        if (roz_runtime_tick(&rt) != ROZ_OK)
            return fail("tick");
    }
    roz_runtime_stats_t st;
    if (roz_runtime_stats(&rt, &st) != ROZ_OK)
        return fail("stats");
    if (roz_runtime_faults(&rt) != 0 || st.runtime.writes != 100 ||
        roz_loopback_counters(&lb).violations != 0)
        return fail("100 ticks without a fault, one frame each");
    roz_runtime_deinit(&rt);
    std::printf("cxx consumer: %zu bytes of roz_runtime_t, 100 ticks, no fault\n", sizeof rt);
    return 0;
}
