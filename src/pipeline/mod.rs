//! The pipeline layer: the order of work from an experiment file to a table. Experiment
//! files and their validation (`experiment`), the runner (`runner`: per map, per case, per
//! encoder, scoring), the timing pass (`timing`), result rows and CSV (`table`), summaries
//! (`summary`), one-knob sweeps (`sweep`), probe sets at scale (`probeset`), the ZH3
//! hallucination-curve fit (`hallucination_fit`), and the plumbing every writer shares:
//! atomic writes and the lock on `results/` (`atomic`), stdout and stderr that never panic (`output`), `--profile` spans (`profile`) and progress bars (`progress`).
//!
//! May use: `math`, `envmap`, `reference`, `encoders`.

pub mod atomic;
pub mod experiment;
pub mod hallucination_fit;
pub mod output;
pub mod probeset;
pub mod profile;
pub mod progress;
pub mod runner;
pub mod summary;
pub mod sweep;
pub mod table;
pub mod timing;
