# SPDX-License-Identifier: Apache-2.0
#
# The two commands of the README:
#   make demo   set up, build, and run the main job
#   make test   set up, build, and run every test
# Both run tools/setup.sh first, which installs what is missing (Debian
# packages, the Python venv, wasm3's sources) and does nothing otherwise.

BUILD  ?= build
CMAKE  ?= cmake
JOBS   ?= $(shell nproc 2>/dev/null || echo 2)

CONFIGURE_FLAGS = -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROZ_WERROR=ON \
                  -DROZGEN_EXECUTABLE=$(CURDIR)/.venv/bin/rozgen \
                  -DROZ_PYTHON=$(CURDIR)/.venv/bin/python \
                  -DROZ_WASM3_SDIST=$(CURDIR)/.cache/pywasm3-0.5.0.tar.gz

.PHONY: all setup build demo test clean

all: build

setup:
	@bash tools/setup.sh

$(BUILD)/build.ninja: | setup
	$(CMAKE) -S . -B $(BUILD) $(CONFIGURE_FLAGS)

build: setup $(BUILD)/build.ninja
	$(CMAKE) --build $(BUILD) -j $(JOBS)

DEMO_DIR = $(BUILD)/demo

# The main job: the sine controller drives a UR5 on the loopback simulator
# for 5 s (500 ticks at 100 Hz) behind the safety filter; the trace and a plot
# of commanded vs applied velocity and joint positions land in $(DEMO_DIR).
demo: build
	@mkdir -p $(DEMO_DIR)
	$(BUILD)/examples/rozrun/rozrun --robot ur5 \
	    --controller $(BUILD)/examples/controllers/sine.wasm --port loopback \
	    --ticks 500 --trace $(DEMO_DIR)/ur5_sine.csv
	.venv/bin/python tools/plot_trace.py $(DEMO_DIR)/ur5_sine.csv $(DEMO_DIR)/ur5_sine.png \
	    --title "UR5, sine controller, loopback simulator"

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD)
