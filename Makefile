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

demo: build
	$(BUILD)/examples/manifest_info/roz_manifest_info

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD)
