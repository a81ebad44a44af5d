# SPDX-License-Identifier: Apache-2.0
#
# The two commands of the README:
#   make demo   set up, build, and run the main job (the G1 walking in MuJoCo
#               under a scripted operator: roz's own walker, or the trained
#               policy G1_WALK_POLICY names)
#   make test   set up, build, and run every test
# Both run tools/setup.sh first, which installs what is missing (Debian
# packages, the Python venv, wasm3's sources) and does nothing otherwise.

BUILD  ?= build
CMAKE  ?= cmake
JOBS   ?= $(shell nproc 2>/dev/null || echo 2)

CONFIGURE_FLAGS = -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROZ_WERROR=ON \
                  -DROZGEN_EXECUTABLE=$(CURDIR)/.venv/bin/rozgen \
                  -DROZ_PYTHON=$(CURDIR)/.venv/bin/python \
                  -DROZ_WASM3_SDIST=$(CURDIR)/.cache/pywasm3-0.5.0.tar.gz \
                  -DROZ_PYTHON_WHEELS=$(CURDIR)/.cache/wheels

# Sanitizer builds (clang, and clang++ for the mujoco port's one C++ file:
# one sanitizer runtime): ASan+UBSan over every C unit test, TSan over the
# threaded ones. Any report fails the run.
SAN_FLAGS = -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
            -DCMAKE_BUILD_TYPE=Debug -DROZ_WERROR=ON \
            -DROZ_INSTALL=OFF -DROZGEN_EXECUTABLE=$(CURDIR)/.venv/bin/rozgen \
            -DROZ_WASM3_SDIST=$(CURDIR)/.cache/pywasm3-0.5.0.tar.gz
# A tree is configured again, with these flags, when the template's
# CMakeLists.txt is newer: a tree configured by an older template may lack
# what the new one needs (ROZ_SOURCE_DIR), which ninja's own re-run of
# CMake would not give it.
FW_CONF = examples/firmware/CMakeLists.txt
SAN_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
          UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
          TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1

.PHONY: all setup setup-ray build install demo train-g1-walk demo-stand demo-loopback campaign test test-asan test-tsan firmware firmware-options stress bench bench-targets bench-firmware fuzz-diff clean

all: build

# its messages on stderr: a target whose output is captured (make bench's
# firmware-options table) gets its own output alone
setup:
	@bash tools/setup.sh >&2

# Ray, roz-campaign's engine for clusters: not in the default set-up (its
# wheel is large); the tests need it (test/campaign/test_campaign_ray.py),
# and so does make bench (the campaigns' Ray row). Idempotent.
setup-ray:
	@bash tools/setup.sh --ray >&2

$(BUILD)/build.ninja: | setup
	$(CMAKE) -S . -B $(BUILD) $(CONFIGURE_FLAGS)

build: setup $(BUILD)/build.ninja
	$(CMAKE) --build $(BUILD) -j $(JOBS)

# Installs the build into PREFIX: libraries, headers, the CMake package, the
# controller SDK, rozgen and the tools (docs/install.md).
PREFIX ?= /usr/local
install: build
	$(CMAKE) --install $(BUILD) --prefix $(PREFIX)

DEMO_DIR = $(BUILD)/demo

# The main job: the 12-joint Unitree G1 walks in MuJoCo for 21 s (10,500
# ticks at 500 Hz) behind the safety filter, its velocity command read from
# the robot's operator inputs, which a scripted operator sets
# (examples/operators/g1_walk.csv: stand, forward 0.5 m/s, stop, turn 0.5
# rad/s, stop). By default (DEMO=policy) the walker is roz's own learned
# policy (examples/policies/g1_walk: an MLP the repository trains itself by
# DAgger on g1_walker.c, train-g1-walk below), deployed by rozgen-nn deploy
# and run inside its deploy sequence (hung on the gantry, moved to the
# stand, let go as the policy takes over at 1.1 s; docs/policies.md,
# section 7). DEMO=walker runs the walker it learnt from
# (examples/controllers/g1_walker.c: a capture-point walker, no learned
# network) under the same script. G1_WALK_POLICY names a trained policy
# instead (unitree_rl_gym's deploy/pre_train/g1/motion.pt; not shipped
# with roz), deployed by rozgen-nn deploy (docs/policies.md). The trace
# (with the simulator's base pose and the inputs), the recording (the
# inputs in it: it replays bit for bit), commanded vs achieved velocity
# (tools/tracking.py), a plot marking the operator's commands, and frames
# of the robot rendered offscreen (where EGL works) land in $(DEMO_DIR).
# test/run_demo.cmake (the tests demo_plot, demo_plot_policy,
# demo_plot_walker) runs the same.
G1_WALK_POLICY ?=
DEMO ?= policy
# the plot's joints: the legs' pitch chain
DEMO_CHANNELS = (hip_pitch|knee|ankle_pitch)_joint/position
DEMO_STAGES =
DEMO_OPERATOR = examples/operators/g1_walk.csv
DEMO_PLAN = forward 0.5 m/s from 1 s
ifneq ($(strip $(G1_WALK_POLICY)),)
DEMO_WALKER = $(BUILD)/examples/controllers/g1_walk.wasm
DEMO_WHAT = $(notdir $(G1_WALK_POLICY)) deployed
demo: setup $(BUILD)/build.ninja
	$(CMAKE) -S . -B $(BUILD) -DROZ_G1_WALK_POLICY=$(abspath $(G1_WALK_POLICY))
	$(CMAKE) --build $(BUILD) -j $(JOBS)
else ifeq ($(DEMO),walker)
DEMO_WALKER = $(BUILD)/examples/controllers/g1_walker.wasm
DEMO_WHAT = roz's own walker (g1_walker.c)
demo: build
else ifeq ($(DEMO),policy)
DEMO_WALKER = $(BUILD)/examples/controllers/g1_walk_dagger.wasm
# the deploy sequence, and the fuel its inference tick declares (209,000
# units, above the G1's default ceiling of 80,000: the integrator's grant,
# docs/policies.md sections 5 and 7)
DEMO_STAGES = --deploy $(BUILD)/examples/controllers/g1_walk_dagger.deploy.toml \
    --param gantry=0:551 --stage-at 0:move --stage-at 550:run --fuel-max 209000
DEMO_WHAT = roz's own walking policy (DAgger on g1_walker.c) deployed
DEMO_PLAN = policy from 1.1 s, forward 0.5 m/s from 1 s
demo: build
else
$(error DEMO=$(DEMO): policy (the default) or walker)
endif
	@mkdir -p $(DEMO_DIR)
	$(BUILD)/tools/rozrun/rozrun --robot unitree_g1_12dof --port mujoco \
	    --controller $(DEMO_WALKER) --ticks 10500 \
	    --operator $(DEMO_OPERATOR) $(DEMO_STAGES) \
	    --trace $(DEMO_DIR)/g1_walk.csv --record $(DEMO_DIR)/g1_walk.mcap
	.venv/bin/python tools/tracking.py $(DEMO_DIR)/g1_walk.csv --operator $(DEMO_OPERATOR)
	.venv/bin/python tools/plot_trace.py $(DEMO_DIR)/g1_walk.csv $(DEMO_DIR)/g1_walk.png \
	    --operator $(DEMO_OPERATOR) --channels '$(DEMO_CHANNELS)' \
	    --title "Unitree G1 (12 joints), $(DEMO_WHAT), under a scripted operator, MuJoCo"
	.venv/bin/python tools/render_frames.py $(DEMO_DIR)/g1_walk.csv \
	    $(DEMO_DIR)/g1_walk_frames.png --at 0,4,9,13,16,21 \
	    --title "Unitree G1 in MuJoCo: $(DEMO_PLAN), stop at 9 s, turn 0.5 rad/s from 12 s, stop at 18 s" \
	    || echo "demo: no offscreen OpenGL here: frames not rendered (tools/render_frames.py)"

# roz's own walking policy trained again (examples/policies/g1_walk/train.py:
# DAgger on g1_walker.c in MuJoCo through the harness collect.c; tens of
# minutes on two cores, so not part of make test): rewrites policy.npz and
# train_log.json there, which the next build deploys (docs/policies.md).
train-g1-walk: build
	OPENBLAS_NUM_THREADS=1 .venv/bin/python examples/policies/g1_walk/train.py \
	    --lib $(BUILD)/examples/controllers/libg1_walk_collect.so

# The balancing stand (examples/controllers/g1_stand.c) holds the 29-joint
# G1 up in MuJoCo for 10 s (5000 ticks at 500 Hz), pushed forward at the
# pelvis with 80 N for 0.1 s half-way; test/run_demo.cmake (demo_plot_stand)
# runs the same and checks the G1 stands at the end.
DEMO_PUSH = 80,0,0@pelvis@2500:2550
demo-stand: build
	@mkdir -p $(DEMO_DIR)
	$(BUILD)/tools/rozrun/rozrun --robot unitree_g1 --port mujoco \
	    --controller $(BUILD)/examples/controllers/g1_stand.wasm --ticks 5000 \
	    --param push=$(DEMO_PUSH) \
	    --trace $(DEMO_DIR)/g1_stand.csv --record $(DEMO_DIR)/g1_stand.mcap
	.venv/bin/python tools/plot_trace.py $(DEMO_DIR)/g1_stand.csv $(DEMO_DIR)/g1_stand.png \
	    --span "5:5.1:push 80 N" --channels '$(DEMO_CHANNELS)' \
	    --title "Unitree G1, balancing stand, MuJoCo, pushed at 5 s"
	.venv/bin/python tools/render_frames.py $(DEMO_DIR)/g1_stand.csv \
	    $(DEMO_DIR)/g1_stand_frames.png --at 0,1,4.9,5.2,5.6,10 \
	    --title "Unitree G1 in MuJoCo: 5 s in, pushed forward with 80 N for 0.1 s" \
	    || echo "demo: no offscreen OpenGL here: frames not rendered (tools/render_frames.py)"

# The first demo: the sine controller drives a UR5 on the loopback simulator
# for 5 s (500 ticks at 100 Hz); commanded vs applied velocity and the joint
# positions are plotted.
demo-loopback: build
	@mkdir -p $(DEMO_DIR)
	$(BUILD)/tools/rozrun/rozrun --robot ur5 \
	    --controller $(BUILD)/examples/controllers/sine.wasm --port loopback \
	    --ticks 500 --trace $(DEMO_DIR)/ur5_sine.csv
	.venv/bin/python tools/plot_trace.py $(DEMO_DIR)/ur5_sine.csv $(DEMO_DIR)/ur5_sine.png \
	    --title "UR5, sine controller, loopback simulator"

# A validation campaign (docs/campaigns.md): the G1's two stands under nine
# families of perturbations (tools/campaigns/g1_stand.toml), on every core;
# the report lands in CAMPAIGN_OUT/index.html (build/campaign/g1_stand/).
# Run again, it resumes; CAMPAIGN_FILE names another campaign file.
# CAMPAIGN_SAMPLES caps the samples a family (empty: the file's).
CAMPAIGN_FILE ?= tools/campaigns/g1_stand.toml
CAMPAIGN_OUT ?= $(BUILD)/campaign/$(basename $(notdir $(CAMPAIGN_FILE)))
CAMPAIGN_SAMPLES ?=
campaign: build
	.venv/bin/python tools/campaign.py run $(CAMPAIGN_FILE) --build $(BUILD) \
	    --out $(CAMPAIGN_OUT) --workers $(JOBS) --quiet \
	    $(if $(CAMPAIGN_SAMPLES),--samples $(CAMPAIGN_SAMPLES))

$(BUILD)-asan/build.ninja: | setup
	$(CMAKE) -S . -B $(BUILD)-asan $(SAN_FLAGS) -DROZ_SANITIZE=address

$(BUILD)-tsan/build.ninja: | setup
	$(CMAKE) -S . -B $(BUILD)-tsan $(SAN_FLAGS) -DROZ_SANITIZE=thread

test-asan: setup $(BUILD)-asan/build.ninja
	$(CMAKE) --build $(BUILD)-asan -j $(JOBS)
	# test_alloc wraps malloc itself, which ASan owns here; it runs in the main build
	cd $(BUILD)-asan && $(SAN_ENV) ctest --output-on-failure -j $(JOBS) -L unit -E test_alloc

test-tsan: setup $(BUILD)-tsan/build.ninja
	$(CMAKE) --build $(BUILD)-tsan -j $(JOBS)
	cd $(BUILD)-tsan && $(SAN_ENV) ctest --output-on-failure -j $(JOBS) -L threads

# The firmware images (examples/firmware/), cross-built for each board
# (boards/: Cortex-M4F, M7, M33) and booted in QEMU: their reports (fingerprint, faults,
# per-tick instruction counts as emulation estimates, heap and stack
# high-water marks) and the footprint table of each against the aims.
# `make test` builds and checks the same images in its own build tree
# (test/firmware/, ctest label firmware).
FW_FLAGS = -G Ninja -DROZ_SOURCE_DIR=$(CURDIR) -DROZ_WERROR=ON \
           -DROZGEN_EXECUTABLE=$(CURDIR)/.venv/bin/rozgen \
           -DROZ_WASM3_SDIST=$(CURDIR)/.cache/pywasm3-0.5.0.tar.gz

# The M4F's and the M7's trees build the ahead-of-time images too, with the
# host build's rozaot (it validates and meters the controller).
FW_AOT = -DROZ_FW_ROZAOT=$(CURDIR)/$(BUILD)/tools/aot/rozaot
$(BUILD)-fw-m4f/build.ninja: $(FW_CONF) | setup build
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m4f $(FW_FLAGS) $(FW_AOT) -DFW_BOARD=mps2-an386

$(BUILD)-fw-m7/build.ninja: $(FW_CONF) | setup build
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m7 $(FW_FLAGS) $(FW_AOT) -DFW_BOARD=mps2-an500

$(BUILD)-fw-stm32/build.ninja: $(FW_CONF) | setup
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-stm32 $(FW_FLAGS) -DFW_BOARD=netduinoplus2

$(BUILD)-fw-m33/build.ninja: $(FW_CONF) | setup
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m33 $(FW_FLAGS) -DFW_BOARD=mps2-an505

# The learned-policy images embed the host build's g1_policy.wasm (the
# bytes the host's fingerprint is computed from).
FW_POLICY = -DROZ_FW_VARIANT=policy \
            -DROZ_FW_POLICY_WASM=$(CURDIR)/$(BUILD)/examples/controllers/g1_policy.wasm
$(BUILD)-fw-m7p/build.ninja: $(FW_CONF) | setup build
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m7p $(FW_FLAGS) $(FW_POLICY) -DFW_BOARD=mps2-an500
$(BUILD)-fw-m4fp/build.ninja: $(FW_CONF) | setup build
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m4fp $(FW_FLAGS) $(FW_POLICY) -DFW_BOARD=mps2-an386

$(BUILD)-fw-m33p/build.ninja: $(FW_CONF) | setup build
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m33p $(FW_FLAGS) $(FW_POLICY) -DFW_BOARD=mps2-an505

# The other robot's images on each board, for make bench-targets only (the
# same controllers on every core): the UR5's sine on the M7, the G1's PD on
# the M4F and the M33 (soft double).
$(BUILD)-fw-m7u/build.ninja: $(FW_CONF) | setup
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m7u $(FW_FLAGS) -DROZ_FW_VARIANT=ur5 \
	    -DFW_BOARD=mps2-an500
$(BUILD)-fw-m4fg/build.ninja: $(FW_CONF) | setup
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m4fg $(FW_FLAGS) -DROZ_FW_VARIANT=g1 \
	    -DFW_BOARD=mps2-an386
$(BUILD)-fw-m33g/build.ninja: $(FW_CONF) | setup
	$(CMAKE) -S examples/firmware -B $(BUILD)-fw-m33g $(FW_FLAGS) -DROZ_FW_VARIANT=g1 \
	    -DFW_BOARD=mps2-an505

FW_TREES = m4f m7 stm32 m33 m7p m4fp
firmware: setup $(foreach t,$(FW_TREES),$(BUILD)-fw-$(t)/build.ninja)
	for t in $(FW_TREES); do $(CMAKE) --build $(BUILD)-fw-$$t -j $(JOBS) || exit 1; done
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an386 $(BUILD)-fw-m4f/roz_fw_ur5_sine.elf 96 64 \
	    "UR5, sine controller, Cortex-M4F (mps2-an386)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an386 $(BUILD)-fw-m4f/roz_fw_ur5_hostile.elf 96 64 \
	    "UR5, endless loop stopped by fuel alone, Cortex-M4F (mps2-an386)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an386 $(BUILD)-fw-m4f/roz_fw_ur5_regs.elf 96 64 \
	    "UR5, sine controller on a port of the firmware's own (no simulator), Cortex-M4F (mps2-an386)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an386 $(BUILD)-fw-m4f/roz_fw_ur5_regs_aot.elf 96 64 \
	    "UR5, sine controller compiled ahead of time (no wasm3), own port, Cortex-M4F (mps2-an386)"
	PYTHON=.venv/bin/python tools/fw_run.sh netduinoplus2 $(BUILD)-fw-stm32/roz_fw_ur5_sine.elf 96 64 \
	    "UR5, sine controller, Cortex-M4F at 168 MHz (netduinoplus2, STM32F405)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an505 $(BUILD)-fw-m33/roz_fw_ur5_sine.elf 96 64 \
	    "UR5, sine controller, Cortex-M33 (mps2-an505, Secure state)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an500 $(BUILD)-fw-m7/roz_fw_g1_pd.elf 128 160 \
	    "Unitree G1, PD controller, Cortex-M7 (mps2-an500)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an500 $(BUILD)-fw-m7/roz_fw_g1_pd_aot.elf 128 160 \
	    "Unitree G1, PD controller compiled ahead of time (no wasm3), Cortex-M7 (mps2-an500)"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an500 $(BUILD)-fw-m7p/roz_fw_g1_policy.elf 320 512 \
	    "Unitree G1, learned policy (LSTM, nn imports), Cortex-M7 (mps2-an500); process() max: an inference tick"
	PYTHON=.venv/bin/python tools/fw_run.sh mps2-an386 $(BUILD)-fw-m4fp/roz_fw_g1_policy.elf 320 512 \
	    "Unitree G1, learned policy, Cortex-M4F (mps2-an386), fuel alone (no clock)"

# The same images built once per part their configuration leaves out, with
# that part put back (tools/fw_options.py): the flash each option saves.
# Long (a build of roz per option and board); `make bench` runs it.
firmware-options: setup
	@.venv/bin/python tools/fw_options.py --build $(BUILD)-fw-options --jobs $(JOBS) \
	    $(FW_FLAGS)

# The tick's cost on every target, in instructions (bench/targets): the
# firmware images' application on x86-64 and aarch64 Linux (the cross tree
# test/aarch64 builds, only its roz_fw_host here) and the Cortex-M4F, M7 and
# M33 images, each under QEMU with its executed blocks counted per part
# (controller, filter, runtime, port); JSON lines into BENCH_OUT/targets.jsonl,
# which bench/report.py renders. Some 15 min; `make bench` runs it.
TARGET_TREES = m4f m7 m33 m7p m4fp m33p m7u m4fg m33g
AARCH64_TREE = $(BUILD)/test/aarch64/tree
bench-targets: setup build $(foreach t,$(TARGET_TREES),$(BUILD)-fw-$(t)/build.ninja)
	for t in $(TARGET_TREES); do $(CMAKE) --build $(BUILD)-fw-$$t -j $(JOBS) || exit 1; done
	$(CMAKE) -DROZ_SOURCE_DIR=$(CURDIR) -DBINARY=$(abspath $(AARCH64_TREE)) -DGENERATOR=Ninja \
	    -DROZGEN_EXECUTABLE=$(CURDIR)/.venv/bin/rozgen -DROZ_PYTHON=$(CURDIR)/.venv/bin/python \
	    -DROZ_WASM3_SDIST=$(CURDIR)/.cache/pywasm3-0.5.0.tar.gz -DROZ_CROSS_ROOT=/ \
	    -DTARGETS=roz_fw_host -P test/aarch64/build_aarch64.cmake
	mkdir -p $(BENCH_OUT)
	.venv/bin/python bench/targets/bench_targets.py --build $(BUILD) --aarch64 $(AARCH64_TREE) \
	    --json $(BENCH_OUT)/targets.jsonl

# Every test: the sanitizer runs first, the whole suite last (the firmware
# images among it, booted in QEMU).
test: setup-ray test-asan test-tsan build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The fault latch under four threads for STRESS_TICKS ticks, under TSan;
# then every port's threads and the runner's with a log callback that
# blocks forever (test_port_conformance's blocking_log, test_runner).
STRESS_TICKS ?= 1000000
stress: setup $(BUILD)-tsan/build.ninja
	$(CMAKE) --build $(BUILD)-tsan -j $(JOBS) --target test_latch_threads \
	  test_runner test_port_conformance
	$(SAN_ENV) ROZ_LATCH_STRESS_TICKS=$(STRESS_TICKS) $(BUILD)-tsan/test/core/test_latch_threads
	cd $(BUILD)-tsan && $(SAN_ENV) ctest --output-on-failure \
	  -R '^(test_runner|test_port_conformance)$$'

# Benchmarks print figures and ratios; they are not tests. `make bench` runs
# every bench with its machine-readable output into BENCH_OUT, builds and
# runs the peer engines (bench/peers: cargo, --locked; only here), and
# writes BENCHMARKS.md from them, and no other file
# (bench/report.py). BENCH_PERIODIC_SECONDS: the 1 kHz runner's run per side
# (60 s by default; shorter for trying it out). BENCH_NOTE: a line on the
# machine for the banner.
BENCH_OUT ?= $(BUILD)/bench/results
BENCH_TICKS ?= 20000
BENCH_ALLOC_TICKS ?= 1000000
BENCH_PERIODIC_SECONDS ?= 60
BENCH_NOTE ?=
bench: build
	rm -rf $(BENCH_OUT) && mkdir -p $(BENCH_OUT)
	$(BUILD)/bench/roz_bench_tick $(BENCH_TICKS) --json $(BENCH_OUT)/tick.jsonl
	$(BUILD)/bench/roz_bench_fuel 9 --json $(BENCH_OUT)/fuel.jsonl
	if [ -x $(BUILD)/bench/roz_bench_nn ]; then \
	    $(BUILD)/bench/roz_bench_nn 5000 --json $(BENCH_OUT)/nn.jsonl; \
	else echo "no Python for rozgen.nn in this build" > $(BENCH_OUT)/nn.skipped; fi
	if [ -x $(BUILD)/bench/roz_bench_aot ]; then \
	    $(BUILD)/bench/roz_bench_aot 20000 --json $(BENCH_OUT)/aot.jsonl; \
	else echo "no ahead-of-time engine in this build (wasm2c, Python)" > $(BENCH_OUT)/aot.skipped; fi
	$(BUILD)/bench/roz_bench_alloc $(BENCH_ALLOC_TICKS) --json $(BENCH_OUT)/alloc.jsonl
	$(BUILD)/bench/roz_bench_periodic $(BENCH_PERIODIC_SECONDS) --json $(BENCH_OUT)/periodic.jsonl
	if [ -x $(BUILD)/bench/roz_bench_can_codec ]; then \
	    $(BUILD)/bench/roz_bench_can_codec --json $(BENCH_OUT)/can_codec.jsonl; \
	else echo "the socketcan port is not in this build" > $(BENCH_OUT)/can_codec.skipped; fi
	$(BUILD)/bench/roz_bench_record $(BENCH_TICKS) $(BUILD)/bench --json $(BENCH_OUT)/record.jsonl
	if [ -x $(BUILD)/bench/roz_bench_g1_latency ]; then \
	    test/run_netns.sh $(BUILD)/bench/roz_bench_g1_latency 5000 77 \
	        --json $(BENCH_OUT)/g1_latency.jsonl; \
	else echo "the unitree/G1 port is not in this build" > $(BENCH_OUT)/g1_latency.skipped; fi
	if [ -x $(BUILD)/bench/roz_bench_mujoco ]; then \
	    $(BUILD)/bench/roz_bench_mujoco 1000 --json $(BENCH_OUT)/mujoco.jsonl; \
	else echo "the mujoco port is not in this build" > $(BENCH_OUT)/mujoco.skipped; fi
	# campaigns: bare rozrun (one, then two at once: the machine's ceiling), one
	# and two local workers, and Ray (make setup-ray: idempotent; docs/campaigns.md)
	$(MAKE) --no-print-directory setup-ray
	if .venv/bin/python -c "import ray" 2>/dev/null; then \
	    test/run_netns.sh .venv/bin/python bench/campaign/bench_campaign.py --build $(BUILD) \
	        --ray --json $(BENCH_OUT)/campaign.jsonl; \
	else .venv/bin/python bench/campaign/bench_campaign.py --build $(BUILD) \
	        --json $(BENCH_OUT)/campaign.jsonl; fi
	PYTHONPATH=$(CURDIR)/codegen .venv/bin/python bench/toml/bench_toml.py \
	    --bench $(BUILD)/bench/roz_bench_toml --root $(CURDIR) --work $(BUILD)/bench/toml \
	    --json $(BENCH_OUT)/toml.jsonl
	# the firmware images' reports and footprints (make firmware: QEMU)
	if $(MAKE) --no-print-directory firmware > $(BENCH_OUT)/firmware.txt 2>&1; then :; else \
	    echo "make firmware failed (its output: $(BENCH_OUT)/firmware.txt)" \
	        > $(BENCH_OUT)/firmware.skipped; rm -f $(BENCH_OUT)/firmware.txt; fi
	# the flash each firmware build option saves (make firmware-options)
	if $(MAKE) --no-print-directory firmware-options > $(BENCH_OUT)/firmware_options.md \
	    2> $(BENCH_OUT)/firmware_options.log; then :; else \
	    echo "make firmware-options failed (its log: $(BENCH_OUT)/firmware_options.log)" \
	        > $(BENCH_OUT)/firmware_options.skipped; rm -f $(BENCH_OUT)/firmware_options.md; fi
	# the tick on every target, in instructions (make bench-targets: QEMU)
	if $(MAKE) --no-print-directory bench-targets > $(BENCH_OUT)/targets.log 2>&1; then :; else \
	    echo "make bench-targets failed (its log: $(BENCH_OUT)/targets.log)" \
	        > $(BENCH_OUT)/targets.skipped; rm -f $(BENCH_OUT)/targets.jsonl; fi
	CARGO_JOBS=$(JOBS) bash bench/peers/run.sh $(BUILD) $(BENCH_OUT) $(CURDIR)/.venv/bin/rozgen
	.venv/bin/python bench/report.py --dir $(BENCH_OUT) --out BENCHMARKS.md \
	    --root $(CURDIR) --command "make bench" --machine-note "$(BENCH_NOTE)" \
	    --binary roz=$(BUILD)/bench/roz_bench_peers_roz \
	    --binary wasmtime=bench/peers/target/release/roz-peer-wasmtime \
	    --binary wasmi=bench/peers/target/release/roz-peer-wasmi

# BENCHMARKS.md's firmware section alone, without the ~100 min of make bench:
# make firmware and make firmware-options into BENCH_FW_OUT, then
# bench/report.py --refresh replaces that section in the existing
# BENCHMARKS.md and keeps every other one (its header says which command
# and commit each section comes from). Some 15 min.
BENCH_FW_OUT ?= $(BUILD)/bench/results-firmware
bench-firmware: setup build
	rm -rf $(BENCH_FW_OUT) && mkdir -p $(BENCH_FW_OUT)
	$(MAKE) --no-print-directory firmware > $(BENCH_FW_OUT)/firmware.txt 2>&1 || \
	    { echo "make firmware failed (its output: $(BENCH_FW_OUT)/firmware.txt)"; exit 1; }
	$(MAKE) --no-print-directory firmware-options > $(BENCH_FW_OUT)/firmware_options.md \
	    2> $(BENCH_FW_OUT)/firmware_options.log || \
	    { echo "make firmware-options failed (its log: $(BENCH_FW_OUT)/firmware_options.log)"; exit 1; }
	.venv/bin/python bench/report.py --dir $(BENCH_FW_OUT) --out BENCHMARKS.md --refresh \
	    --root $(CURDIR) --command "make bench-firmware"

# The long differential run (fuzz/README.md): generated and wasm-tools smith
# modules on roz's wasm3 against wasm-interp, then fuzz_controller from them
# when build-asan has it. FUZZ_DIFF_SECONDS per stage.
FUZZ_DIFF_SECONDS ?= 600
fuzz-diff: build
	bash fuzz/diff/long_run.sh $(FUZZ_DIFF_SECONDS)

clean:
	rm -rf $(BUILD) $(BUILD)-asan $(BUILD)-tsan $(foreach t,$(FW_TREES) m33p m7u m4fg m33g,$(BUILD)-fw-$(t)) \
	    $(BUILD)-fw-options
