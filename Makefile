# MotionMap's two commands. Both install missing Debian packages first (scripts/install-deps.sh).
#   make demo   build (Release) the CLI and Studio and run the main job on the built-in sample
#   make test   check the formatting, then build everything and run the whole test suite through
#               ctest: Release, then ASan+UBSan (library, CLI, their tests, and every parser's
#               libFuzzer target for FUZZ_SECONDS each)
# Also: make package (the .deb, docs/install.md), make format / format-check, make bench.
JOBS ?= $(shell nproc)
FUZZ_SECONDS ?= 30
BUILD ?= build

# cmake's -G for a new build directory $(1): Ninja when it is there. A shell substitution, so it
# is decided when the recipe runs, after `deps` may have installed ninja in the same run; nothing
# for a directory configured before (cmake refuses to switch generators).
cmake_gen = $$(test -f $(1)/CMakeCache.txt || { command -v ninja >/dev/null 2>&1 && echo -G Ninja; })

.PHONY: all deps build demo test test-release configure-sanitize test-sanitize test-fuzz bench \
        package format format-check clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) $(call cmake_gen,$(BUILD)) -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

# The main job on the built-in sample: the six maps of a golf-like swing, as a figure; then, when
# a display is there ($$DISPLAY or $$WAYLAND_DISPLAY set), MotionMap Studio opened on the same clip.
# Builds only the two programs it runs (in the same build directory as `make test`, which builds
# the rest).
STUDIO := $(BUILD)/apps/gui/motionmap-studio
demo: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS) --target motionmap motionmap-studio
	@mkdir -p out
	$(BUILD)/apps/cli/motionmap sample --kind swing -o out/sample-swing.bvh
	$(BUILD)/apps/cli/motionmap info out/sample-swing.bvh
	$(BUILD)/apps/cli/motionmap figure out/sample-swing.bvh -o out/sample-swing-maps.png
	@echo "wrote out/sample-swing-maps.png"
	@if [ -z "$$DISPLAY$$WAYLAND_DISPLAY" ]; then \
	  echo "no display (DISPLAY and WAYLAND_DISPLAY unset): MotionMap Studio not opened"; \
	elif [ ! -x $(STUDIO) ]; then \
	  echo "$(STUDIO) was not built (Qt 6 Widgets missing?): MotionMap Studio not opened"; \
	else \
	  echo "opening MotionMap Studio on out/sample-swing.bvh (close the window to finish)"; \
	  $(STUDIO) out/sample-swing.bvh; \
	fi

# format-check first: a badly formatted tree fails before anything is built.
test: format-check test-release test-sanitize

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The library, the CLI, their tests and every parser's libFuzzer target, built once with clang
# under AddressSanitizer + UndefinedBehaviorSanitizer (build-sanitize): what parses files, places
# frames and meets bad input. Studio, the benchmarks, and the tests of the numerical kernels and of
# the methods against their references (tests/CMakeLists.txt) are left out: they run in the
# Release build. Line tables only (-gline-tables-only): all a sanitizer's stack trace needs.
# One ctest test per GoogleTest suite there (tests/gtest_suites.cmake): an instrumented test
# executable takes about 0.5 s to start. The fuzzers (fuzz/) are ctest tests too, each fuzzing
# FUZZ_SECONDS (30 s in `make test`; longer on its own: make test-fuzz FUZZ_SECONDS=600).
SANITIZE_DIR := build-sanitize
configure-sanitize: deps
	cmake -S . -B $(SANITIZE_DIR) $(call cmake_gen,$(SANITIZE_DIR)) \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
	  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DMOTIONMAP_SANITIZE=ON \
	  -DMOTIONMAP_FUZZ=ON -DMOTIONMAP_FUZZ_SECONDS=$(FUZZ_SECONDS) \
	  -DMOTIONMAP_BUILD_BENCH=OFF -DMOTIONMAP_BUILD_GUI=OFF

SANITIZE_ENV := ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
test-sanitize: configure-sanitize
	cmake --build $(SANITIZE_DIR) -j $(JOBS)
	cd $(SANITIZE_DIR) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS)

test-fuzz: configure-sanitize
	cmake --build $(SANITIZE_DIR) -j $(JOBS) --target motionmap_fuzzers
	cd $(SANITIZE_DIR) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS) -L fuzz

bench: build
	$(BUILD)/bench/motionmap_bench

# The .deb (CPack) of everything `cmake --install` installs: $(BUILD)/motionmap_<version>_<arch>.deb.
package: build
	cd $(BUILD) && cpack -G DEB

format:
	find src apps tests bench fuzz python -name '*.h' -o -name '*.cpp' | xargs clang-format -i

# Fails, naming the files and lines, when a source differs from the committed .clang-format.
format-check: deps
	find src apps tests bench fuzz python -name '*.h' -o -name '*.cpp' | xargs clang-format --dry-run -Werror

clean:
	rm -rf $(BUILD) $(SANITIZE_DIR) out
