//! Charts (plotters, bundled font), each drawn twice from the same code: into a bitmap (the
//! PNG) and into an SVG string (for papers; text as `<text>` elements with the full labels,
//! laid out from the bitmap font's measured widths): rmse per encoder per map (dots, or a heatmap
//! of ratios to the baseline), error against cost with the Pareto front, convergence curves of sweeps, and the lightmap blending line
//! chart. Every chart reads its CSV by column name; a chart whose columns are absent is not
//! drawn and says why (the report prints the reason).
//!
//! File formats read here (also in docs/report.md):
//! - `table.csv` (the runner's): `map`, `encoder`, `rmse`; optional `metric` (rows of `exact`
//!   are charted when present), `fit_ns` (the error-against-time chart needs it).
//! - `sweep*.csv`: `knob,value,rmse,time_ns,label` — one chart per knob, one line per label
//!   (more than 8 labels: per encoder, the median and worst RMSE over its series);
//!   `time_ns` may be empty; an optional `reference` column says what rmse is measured against.
//! - `blend*.csv`: `t,method,irradiance_at_n_r,irradiance_at_n_g,irradiance_at_n_b,rmse` —
//!   `rmse` may be empty; an optional `set` column gives one chart per lighting set.
//!
//! One concept per file: `draw.rs` (the outcome, drawing on both backends), `marks.rs` (an
//! encoder's marker in its style, `report::style`), `axes.rs` (log-axis bounds and ticks),
//! `rows.rs` (which rows a table chart reads), `dots.rs` (rmse per encoder and map),
//! `heatmap.rs` (the same as ratios to a baseline, for many maps × encoders), `cost.rs` (error
//! against cost, the Pareto front, point labels),
//! `lines.rs` (line panels and their legend column), `sweeps.rs`, `convergence.rs` (a sweep
//! with more series than a legend holds) and `blending.rs`.

mod axes;
mod backend;
mod blending;
mod convergence;
mod cost;
mod dots;
mod draw;
mod heatmap;
mod lines;
mod marks;
mod rows;
mod sweeps;
#[cfg(test)]
mod tests;

pub use blending::{blend_charts, is_blend};
pub use cost::{error_vs_cost, Cost, CostContext};
pub use dots::rmse_dots;
pub use draw::Outcome;
pub use sweeps::{is_sweep, sweep_charts};
