//! Link setup of the RP2040 firmware.
//!
//! Copies the workspace's `memory.x` (the RP2040 memory map) into `OUT_DIR`, puts that
//! directory on the linker search path, and passes the linker scripts to the binary
//! only (`rustc-link-arg-bins`), so test and doc harnesses are untouched:
//!
//! * `link.x` (cortex-m-rt): vector table and sections; it includes `memory.x`.
//! * `link-rp.x` (embassy-rp): places the second-stage bootloader (`.boot2`).
//! * `defmt.x` (defmt): the log string table.
//!
//! It also passes the git commit to the firmware (`FOOSBALL_GIT_HASH`) and defaults
//! the crate's defmt log level to `info` (see the end of `main`).

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let manifest_dir =
        PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let memory_x = manifest_dir.join("../../memory.x");
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));

    let contents = fs::read(&memory_x)
        .unwrap_or_else(|err| panic!("cannot read {}: {err}", memory_x.display()));
    fs::write(out.join("memory.x"), contents).expect("cannot write memory.x into OUT_DIR");

    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");

    // `--nmagic`: do not page-align sections; flash and RAM are not paged, and page
    // alignment would waste flash between BOOT2 and the vector table.
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tlink-rp.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");

    // The firmware's git commit for the diagnostics Feature report
    // (`FOOSBALL_GIT_HASH`, 12 hex digits; "unknown" outside a git checkout, e.g.
    // a source tarball). Rebuilt when HEAD or a branch moves.
    let repo = manifest_dir.join("../..");
    let hash = std::process::Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(&repo)
        .output()
        .ok()
        .filter(|out| out.status.success())
        .and_then(|out| String::from_utf8(out.stdout).ok())
        .map(|text| text.trim().to_owned())
        .filter(|text| !text.is_empty())
        .unwrap_or_else(|| "unknown".to_owned());
    println!("cargo:rustc-env=FOOSBALL_GIT_HASH={hash}");
    for watched in [".git/HEAD", ".git/refs/heads", ".git/packed-refs"] {
        let path = repo.join(watched);
        if path.exists() {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    }

    // defmt logs only errors unless DEFMT_LOG says otherwise; default this crate's
    // own messages to `info` (a DEFMT_LOG set by the user wins and applies to all
    // crates).
    println!("cargo:rerun-if-env-changed=DEFMT_LOG");
    if env::var_os("DEFMT_LOG").is_none() {
        println!("cargo:rustc-env=DEFMT_LOG=info");
    }
}
