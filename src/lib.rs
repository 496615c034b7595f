//! The `karstgen` command: every user-facing task of karstgen from any folder.
//!
//! `karstgen run SCENE` runs the pipeline (in this process, stage after stage, skipping those
//! that are up to date); `inspect`, `diff`, `metrics`, `ensemble`, `calibrate` and `render` work on its
//! outputs or on any network file. Paths on the command line are relative to the working
//! folder; the data files a scene names are relative to the scene's own folder. `cargo xtask`
//! (for developers) runs the same code.

pub mod cli;
