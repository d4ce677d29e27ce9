//! # cramp — a reference Material Point Method with explicit cracks
//!
//! Modules follow the stages of the algorithm as the papers name them
//! (Nairn 2003, "MPM calculations with explicit cracks", appendix A):
//!
//! * [`dim`] — the only place that knows the spatial dimension.
//! * [`exact`] — correctly rounded, order-independent summation (every grid sum uses it).
//! * [`expr`] — expressions of position and time in scene files, compiled to f64 programs.
//! * [`motion`] — prescribed boundary motion, tractions and time functions (2D and 3D).
//! * [`fingerprint`] — bit fingerprints of final states for the golden snapshots.
//! * [`grid`] — the background grid and its per-velocity-field nodal arrays.
//! * [`shape`] — linear and uGIMP shape functions.
//! * [`particles`] — material points, struct-of-arrays.
//! * [`material`] — constitutive laws.
//! * [`crack`] — crack geometry, line crossing, velocity fields, surfaces.
//! * [`simd`] — runtime choice of AVX2 copies of the hot loops (same bits).
//! * [`step`] — tasks 0–8 and the four update schemes (USL, MUSL, USF, USAVG).
//! * [`check`] — invariant checks of the checked mode.
//! * [`simulation`] — the state of a run and its time loop.
//! * [`fracture`] — J-integral, K, growth criteria.
//! * [`fea`] — the static Q4 finite-element solver used for comparison.
//! * [`scene`] — TOML scene input and validation (2D); [`scene3d`] — 3D scenes, and the
//!   dimension of a scene file; [`scene_override`] — `--set PATH=VALUE` overrides; [`stl`] — closed STL surfaces for 3D bodies.
//! * [`budget`] — the memory a scene needs, checked before it is built.
//! * [`output`] — history CSV, summary JSON, VTK snapshots.
//! * [`report`] — plots and the report index.
//! * [`verify`] — the verification cases, `cramp verify` and `cramp compare`.

pub mod budget;
pub mod check;
pub mod contact;
pub mod crack;
pub mod dim;
pub mod exact;
pub mod expr;
pub mod fea;
pub mod fingerprint;
pub mod fracture;
mod gather3;
pub mod grid;
pub mod material;
pub mod motion;
pub mod output;
pub mod particles;
pub mod report;
pub mod scene;
pub mod scene3d;
pub mod scene_override;
pub mod scene_rotate;
pub mod shape;
pub mod simd;
pub mod simulation;
pub mod step;
pub mod stl;
pub mod verify;
