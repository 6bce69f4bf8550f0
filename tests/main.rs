//! Integration tests, one crate (ripgrep-style hub). Every GPU test runs under the Khronos
//! validation layer and fails on any message.
//!
//! - `support`: shared helpers (validated renderer, scene loading, models folder, the binary).
//! - `gpu`: rendering, the f64 truth agreement and its teeth.
//! - `methods`: every method against its own f64 formula, swapped-shader teeth, paper bounds.
//! - `bench`: bench.json against its schema, CSV, charts, claims (structure only, no speeds).
//! - `cli`: exit codes and exact error texts of the built `shadelab` binary.
//! - `corpus`: corpus shards merged == one unsharded run, merge's refusals, a corrupt OBJ, restart,
//!   the Slurm example on a single-node Slurm (skipped unless root with slurm-wlm).
//! - `compare`: summary.json against its schema, heatmaps, CSV, --fail-above.
//! - `stress`: stress.json against its schema, NaN counts, the specular claim, --replay.
//! - `float16`: the float16 programs (issue 23): float32 SPIR-V unchanged, float16-only
//!   arithmetic, binary16 rounding and overflow, compare/stress `--precision f16`, replay.
//! - `shaders`: spirv/ freshness, spirv-val, the uniform-block layout against its Rust twin.
//! - `software`: the software engine against Vulkan (coverage, colours) and its f64 twins.
//! - `report`: the HTML report: links, every method's parts, escaping; headless Chromium (no
//!   error, no failed resource, the script runs, a screenshot that is not blank), with teeth.
//! - `isa`: RADV null-device statistics: identical runs, the Phong order per family, 16 extra
//!   multiplications cost more, a refused family is reported, isa.json against its schema.
//! - `isa_mobile`: the families of `make compilers` (Qualcomm, Arm, Broadcom, Intel Meteor Lake
//!   to Panther Lake): every method in float32 and float16, the Phong order, refusals.
//! - `isa_apple`: Apple's G13 through Honeykrisp (`make compilers`): every method in float32 and
//!   float16, the cycle model's bound unit, the Phong order, identical runs, refused chips.
//! - `store`: the compile store: figures from it equal fresh ones on every set-up family, a
//!   corrupt entry compiled again, a changed compiler identity misses, two processes at once.
//! - `layout`: the layers of src/lib.rs point one way; ash only in gpu/vk, clap only in cli.
//! - `docs`: the documentation agrees with the tool: every count of methods, GPU families and
//!   vendors is the library's, every path layout.md and ARCHITECTURE.md name exists, every link
//!   between the pages resolves (the figures' rows included), no process words, closed fences.
//! - `citations`: every `docs/formulas.md#<anchor>` the sources, docs and the method table cite
//!   is a heading of docs/formulas.md; nothing cites a file a clone lacks.
//! - `fuzz`: the OBJ and scene readers on mutated inputs (smoke run; scripts/fuzz.sh runs 1M).
//! - `prove`: proof.json against its schema, its two domains, bounds above found values, --replay
//!   of a found input (a triangle's and an edge's), the help naming the angle's domain.
//! - `tune`: tune.json against its schema, the answer per cost model, the tuned files through
//!   compare within their proven bounds, a form's cost independent of its coefficients.
//! - `yours`: `--method-file` (issue 28): the examples of docs/examples/methods/ through compare,
//!   stress, isa and report; the bit trick's error against its known figure; the refusals.
//! - `explore`: `shadelab explore`'s API with a real HTTP client (its figures are compare's and
//!   isa's, a broken GLSL's line, an upload, the guard, superseding, a hung render, kill -9) and
//!   its page in headless Chromium.
//! - `one_row`: a test-only method, its GLSL file and one row (issue 38), through verify on both
//!   engines, stress, prove, list and the report's answer.
//! - `inputs`: glTF 2.0 and PLY beside OBJ: hand-checked node transforms, every encoding the
//!   same mesh, bad files (exit 2, file and object), mixed folders through report, corpus and
//!   tune; glTF converted from the shared models by obj2gltf against their OBJ.
//! - `hostile`: the contract under hostile input (issue 49): a probe per test (a byte-order mark,
//!   an edited tuned file, unknown chips, half a size, absurd counts, in-place and unmarked
//!   outputs, outputs over inputs, kill -9 / SIGTERM / SIGINT, an image too big for memory).
//! - `models`: the real-world meshes of ../shared/models (`SHADELAB_MODELS`), skipped if absent.
mod bench;
mod calibrate;
mod citations;
mod cli;
mod compare;
mod corpus;
mod costs;
mod docs;
mod explore;
mod explore_page;
mod float16;
mod fuzz;
mod gpu;
mod hostile;
mod inputs;
mod isa;
mod isa_apple;
mod isa_mobile;
mod layout;
mod methods;
mod models;
mod one_row;
mod prove;
mod report;
mod shaders;
mod software;
mod store;
mod stress;
mod support;
mod tune;
mod workers;
mod yours;
