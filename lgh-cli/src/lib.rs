//! The parts of the `lgh` command-line tool that other crates use: its PLY point-cloud reader
//! and writer ([`ply`]), which the fuzz target `ply` drives (`fuzz/README.md`).

pub mod ply;
