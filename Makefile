# MotionMap's two commands. Both install missing Debian packages first (scripts/install-deps.sh).
#   make demo   build (Release) the CLI and Studio and run the main job on the built-in sample
#   make test   check the formatting, then build everything and run the whole test suite through
#               ctest: Release, then ASan+UBSan (library, CLI and their tests), then every
#               parser's libFuzzer target for FUZZ_SECONDS each
# Also: make package (the .deb, docs/install.md), make format / format-check, make bench.
JOBS ?= $(shell nproc)
FUZZ_SECONDS ?= 30
BUILD ?= build

# cmake's -G for a new build directory $(1): Ninja when it is there. A shell substitution, so it
# is decided when the recipe runs, after `deps` may have installed ninja in the same run; nothing
# for a directory configured before (cmake refuses to switch generators).
cmake_gen = $$(test -f $(1)/CMakeCache.txt || { command -v ninja >/dev/null 2>&1 && echo -G Ninja; })

.PHONY: all deps build demo test test-release test-sanitize test-fuzz bench package format \
        format-check clean

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
test: format-check test-release test-sanitize test-fuzz

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The library, the CLI and their tests under AddressSanitizer + UndefinedBehaviorSanitizer: what
# parses files, places frames and meets bad input. Studio, the benchmarks, and the tests of the
# numerical kernels and of the methods against their references (tests/CMakeLists.txt) are left
# out: they run in the Release build, and were most of this build's time. -g1: line tables, all a
# sanitizer's stack trace needs, at a fraction of full debug information's compile and link time.
# One ctest test per GoogleTest suite there (tests/gtest_suites.cmake): an instrumented test
# executable takes about 0.5 s to start.
test-sanitize: deps
	cmake -S . -B build-asan $(call cmake_gen,build-asan) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
	  -DMOTIONMAP_SANITIZE=ON -DMOTIONMAP_BUILD_BENCH=OFF -DMOTIONMAP_BUILD_GUI=OFF
	cmake --build build-asan -j $(JOBS)
	cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS)

# libFuzzer targets (clang, ASan+UBSan) seeded with the real files in ../shared/data; each runs
# FUZZ_SECONDS as a ctest test, one per core (30 s in `make test`; longer on demand:
# make test-fuzz FUZZ_SECONDS=600). Line tables only, as for the sanitizer build.
test-fuzz: deps
	cmake -S . -B build-fuzz $(call cmake_gen,build-fuzz) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
	  -DCMAKE_CXX_COMPILER=clang++ -DMOTIONMAP_FUZZ=ON -DMOTIONMAP_FUZZ_SECONDS=$(FUZZ_SECONDS) \
	  -DMOTIONMAP_BUILD_TESTS=OFF -DMOTIONMAP_BUILD_BENCH=OFF -DMOTIONMAP_BUILD_CLI=OFF \
	  -DMOTIONMAP_BUILD_GUI=OFF -DMOTIONMAP_BUILD_RENDER=OFF
	cmake --build build-fuzz -j $(JOBS)
	cd build-fuzz && ctest --output-on-failure -j $(JOBS)

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
	rm -rf $(BUILD) build-asan build-fuzz out
