# shadelab: the two commands of the README's quick start are `make demo` and `make test`.
# Each installs the Debian/Ubuntu packages it needs when missing (scripts/install-deps.sh).
CARGO ?= cargo
BIN := target/release/shadelab
# Real-world meshes for the tests: ../shared/models when present (never copied into the repo).
SHADELAB_MODELS ?= $(if $(wildcard ../shared/models/*.obj),$(abspath ../shared/models),)
export SHADELAB_MODELS

.PHONY: demo test build deps vendors compilers spirv scenes bench fuzz clean

deps:
	scripts/install-deps.sh run build test

build:
	scripts/install-deps.sh run build
	$(CARGO) build --release --locked

## The other vendors' compilers of `shadelab isa` (Intel, NVIDIA, AMD TeraScale: docs/isa.md),
## in the user's cache. A route that fails names its step and leaves the others and the rest of
## the job going: its tests then skip (and fail under SHADELAB_REQUIRE_VENDORS=1, as in CI).
vendors:
	-scripts/setup-vendors.sh

## The compilers of `shadelab isa`'s phone, board, Apple and newest Intel families (Qualcomm
## Adreno, Arm Mali, Broadcom VideoCore, Apple G13; Intel Meteor Lake to Panther Lake:
## docs/isa.md), built from
## Debian's Mesa 25.0.7 source into the user's cache: long the first time (docs/isa.md gives
## the minutes), a second afterwards. `make test` without it skips those families' tests and
## says so.
compilers:
	scripts/build-compilers.sh

## The main job on the shipped scenes: compare, bench, stress, one HTML page; prints the path of
## out/report/index.html (last line of stdout). Progress (each step with its time) and the total
## time of the report go to stderr.
demo: build vendors
	@start=$$(date +%s); $(BIN) report --scenes scenes --out out/report && \
	echo "make demo: the report took $$(( $$(date +%s) - start )) s" >&2

## The whole test suite (unit, GPU under the validation layer, CLI, real-world models). The
## glTF converter of the mesh-input tests (obj2gltf, npm) goes into the user's cache.
test:
	scripts/install-deps.sh run build test
	-scripts/setup-vendors.sh
	-scripts/setup-converters.sh
	$(CARGO) build --release --locked
	$(CARGO) test --release --locked
	@scripts/build-compilers.sh --check >/dev/null 2>&1 || echo "make test: not covered: shadelab isa on the Qualcomm, Arm, Broadcom, Apple and Intel Meteor Lake to Panther Lake families (their tests skipped); run make compilers, then make test" >&2

## Regenerate spirv/ from glsl/ with shaderc (a test fails when spirv/ is stale).
spirv: build
	$(BIN) shaders --glsl glsl --spirv spirv
	$(CARGO) build --release --locked

## Regenerate the shipped meshes of scenes/ (a test fails when they are stale).
scenes: build
	$(BIN) mesh --shipped scenes

## Benchmarks of README "Performance" (not part of the tests).
bench: build
	scripts/bench.sh

## Fuzz the OBJ, scene, replay, glTF and PLY readers, 1,000,000 inputs (README "Fuzzing"; not part of the tests,
## which run a 20,000-input smoke run of the same harness).
fuzz:
	scripts/install-deps.sh run build
	scripts/fuzz.sh

clean:
	$(CARGO) clean
	rm -rf out
