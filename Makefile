# gr-nrsar: the commands of the README. Each target installs the Debian packages it needs
# (as root on Debian 12), configures with /usr/bin/python3, builds with ccache and -j2.

BUILD      ?= build
PREFIX     ?= /usr/local
JOBS       ?= 2
PYTHON     := /usr/bin/python3
DEMO_OUT   ?= demo-out
# the base station decodes a slot's code blocks on two threads where there are two cores
DEMO_RX_THREADS ?= $(shell [ "$$(nproc)" -gt 1 ] && echo 2 || echo 1)

# gnuradio-companion needs the introspection data of GTK 3 and PangoCairo (its
# gi.require_version checks), which the gnuradio package does not depend on: without them it
# stops with "Namespace Gtk not available". Cairo for pygobject (a gnuradio dependency, named
# for GRC's sake) and GTK's SVG loader for the Adwaita icons (a Recommends of GTK).
GRC_PACKAGES := gir1.2-gtk-3.0 gir1.2-pango-1.0 python3-gi-cairo librsvg2-common

DEB_PACKAGES := build-essential cmake ccache pkg-config git \
	gnuradio gnuradio-dev gr-radar libvolk2-dev libfftw3-dev pybind11-dev \
	python3-dev python3-numpy python3-matplotlib python3-yaml python3-pygccxml castxml \
	libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth zlib1g-dev clang libclang-rt-14-dev \
	python3-soapysdr python3-gdal python3-pyproj python3-distributed $(GRC_PACKAGES)

CMAKE_FLAGS := -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=$(PREFIX) \
	-DPython_EXECUTABLE=$(PYTHON) -DPYTHON_EXECUTABLE=$(PYTHON) -DENABLE_DOXYGEN=OFF

.PHONY: all deps configure runtime build test test-sanitize fuzz install demo bench soak clean

all: build

# Installs only what is missing, so a prepared machine pays nothing.
deps:
	@missing=$$(for p in $(DEB_PACKAGES); do \
		dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "install ok installed" || echo $$p; \
	done); \
	if [ -n "$$missing" ]; then \
		echo "installing Debian packages:" $$missing; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -q && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -q --no-install-recommends $$missing; \
	fi

# Reconfigured when the top CMakeLists.txt is newer: a build directory configured before it
# defined nrsar_runtime learns the target (cmake leaves an unchanged cache alone: touch).
$(BUILD)/CMakeCache.txt: CMakeLists.txt
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)
	touch $@

configure: deps $(BUILD)/CMakeCache.txt

# What `make install` copies: the library, the bindings, the Python package, the apps and the
# GRC blocks, without the GoogleTests and benchmarks (`make build` and `make test` add those).
runtime: configure
	cmake --build $(BUILD) -j$(JOBS) --target nrsar_runtime

build: configure
	cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# The GoogleTest kernel tests under AddressSanitizer + UndefinedBehaviorSanitizer, in their own
# Debug build directory (no Python, no benchmarks): any report stops the test (halt_on_error).
SAN_BUILD  ?= build-sanitize
SAN_FLAGS  := -fsanitize=address,undefined -fno-omit-frame-pointer
SAN_ENV    := ASAN_OPTIONS=halt_on_error=1:abort_on_error=0:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitize/lsan.supp:print_suppressions=0

test-sanitize: deps
	cmake -S . -B $(SAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="$(SAN_FLAGS)" \
		-DENABLE_PYTHON=OFF -DENABLE_BENCHMARKS=OFF -DENABLE_DOXYGEN=OFF \
		-DPython_EXECUTABLE=$(PYTHON) -DPYTHON_EXECUTABLE=$(PYTHON)
	$(SAN_ENV) cmake --build $(SAN_BUILD) -j$(JOBS)
	cd $(SAN_BUILD) && $(SAN_ENV) ctest --output-on-failure -j$(JOBS)

# libFuzzer targets (every tests/fuzz/fuzz_*.cc) with the library, built by clang under
# ASan + UBSan in their own directory, each run FUZZ_SECONDS with a corpus seeded from
# tests/fuzz/corpus/<target>/; crashes land in tests/fuzz/regressions/<target>/ (see
# tests/fuzz/README.md), which the ordinary build replays as ctest cases.
FUZZ_BUILD   ?= build-fuzz
FUZZ_SECONDS ?= 60

fuzz: deps
	cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=Debug \
		-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DENABLE_FUZZ=ON \
		-DENABLE_GTESTS=OFF -DENABLE_PYTHON=OFF -DENABLE_BENCHMARKS=OFF -DENABLE_DOXYGEN=OFF \
		-DPython_EXECUTABLE=$(PYTHON) -DPYTHON_EXECUTABLE=$(PYTHON)
	cmake --build $(FUZZ_BUILD) -j$(JOBS) --target nrsar_fuzz
	FUZZ_SECONDS=$(FUZZ_SECONDS) tests/fuzz/run $(FUZZ_BUILD)

install: runtime
	cmake --install $(BUILD)
	ldconfig

# The demo runs the installed module, as a user would: the one ISAC graph (docs/isac.md) at
# the paper scenario. Payload: GPL-3 (on every Debian machine) repeated 100 times = 3,514,900
# bytes, 96 TBs of the 2 s aperture, the TS 38.212 UL-SCH at qam256 MCS 27 (256-QAM, R 0.93);
# the JSON object is the last line. --rx-fuse on: filter and range IFFT in one block per
# branch (the same images, less CPU and memory: docs/performance.md, "Third pass").
demo: install
	mkdir -p $(DEMO_OUT)
	for i in $$(seq 100); do cat /usr/share/common-licenses/GPL-3; done > $(DEMO_OUT)/payload.bin
	$(PREFIX)/bin/nrsar-isac --preset paper --scene paper3 --filter wf --snr-db -20 \
		--payload $(DEMO_OUT)/payload.bin --bs-snr-db 50 --cfo-hz 9000 --delay-samples 1234 \
		--coding nr-ldpc --mcs-table qam256 --mcs 27 --rx-threads $(DEMO_RX_THREADS) \
		--rx-fuse on --out $(DEMO_OUT) --json

# Kernel benchmarks (Google Benchmark, outside ctest so VOLK uses its fast kernels), then
# the flowgraph-level comparisons with peers; results land in docs/bench/.
bench: build install
	mkdir -p docs/bench
	for b in $(BUILD)/bench/bench_*; do \
		[ -x "$$b" ] || continue; \
		"$$b" --benchmark_min_time=0.2 --benchmark_out_format=csv \
			--benchmark_out=docs/bench/$$(basename $$b).csv; \
	done
	$(PREFIX)/bin/nrsar-bench --out docs/bench
	/usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --published --blocks 1000 \
		> docs/bench/nr_bler_published.md
	/usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --lena --blocks 1000 \
		> docs/bench/nr_bler_lena.md
	/usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --sionna --blocks 1000 \
		> docs/bench/nr_bler_sionna.md

# perf: soak test (issue #8), on demand, not in make test: 10 minutes of radar time at
# paper scale through the whole chain; fails when the RSS grows (docs/soak.md).
SOAK_OUT     ?= soak-out
SOAK_MINUTES ?= 10
soak: install
	$(PREFIX)/bin/nrsar-soak --preset paper --minutes $(SOAK_MINUTES) --interval-s 5 \
		--out $(SOAK_OUT)

clean:
	rm -rf $(BUILD) $(SAN_BUILD) $(FUZZ_BUILD) $(DEMO_OUT)
