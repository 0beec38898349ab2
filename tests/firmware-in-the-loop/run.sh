#!/usr/bin/env bash
# Firmware in the loop: runs the release firmware ELF in the emulated RP2040
# (rp2040js, patched) with eight PS/2 mice and a USB host. Exits non-zero if any
# check fails.
#
# Needs the firmware built first:
#   cargo build -p foosball-firmware --target thumbv6m-none-eabi --release
# Installs Node.js (Debian packages nodejs, npm) if it is missing, then the pinned
# npm dependencies (`npm ci`, which applies patches/ through the postinstall script).
#
# Environment: FIRMWARE_ELF (another ELF), FIRMWARE_UF2 (another UF2), CARGO_TARGET_DIR
# (where the build went), FITL_LOG=0 (do not print the firmware's defmt log).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

step() { printf '\n==> %s\n' "$*"; }

node_ok() {
    command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1 &&
        [ "$(node -p 'Number(process.versions.node.split(".")[0])')" -ge 18 ]
}

if ! node_ok; then
    step "installing Node.js (Debian packages nodejs, npm)"
    sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm
    node_ok || { echo "Node.js >= 18 is required, found $(node --version 2>/dev/null || echo none)" >&2; exit 1; }
fi

step "firmware in the loop: npm ci (rp2040js $(node -p 'require("./package.json").dependencies.rp2040js'), patched)"
npm ci --no-audit --no-fund --loglevel=error

# The UF2 a builder flashes (firmware/make-uf2, elf2uf2-rs), unless one is given:
# made again when missing or older than the ELF. test/uf2.test.mjs checks it and
# test/firmware.test.mjs boots from it.
repo=$(cd ../.. && pwd)
target_dir=${CARGO_TARGET_DIR:-target}
case $target_dir in /*) ;; *) target_dir=$repo/$target_dir ;; esac
elf=${FIRMWARE_ELF:-$target_dir/thumbv6m-none-eabi/release/foosball-firmware}
if [ -z "${FIRMWARE_UF2:-}" ] && { ! [ -f "$elf.uf2" ] || [ "$elf" -nt "$elf.uf2" ]; }; then
    step "firmware in the loop: making the UF2 from $elf"
    CARGO_TARGET_DIR=$target_dir "$repo/firmware/make-uf2" "$elf" "$elf.uf2"
fi

step "firmware in the loop: node $(node --version)"
start=$(date +%s)
node --test test/uf2.test.mjs test/firmware.test.mjs test/latency.test.mjs test/wire.test.mjs test/feature.test.mjs
echo "firmware in the loop: passed in $(($(date +%s) - start)) s"
