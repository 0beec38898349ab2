// Feature reports on the control pipe: diagnostics, settings (applied to the mice,
// kept across a power cycle) and the restart into the ROM's USB bootloader.
import { before, describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { crc32 } from 'node:zlib';
import { join } from 'node:path';
import { createRig, firmwareUf2Path, REPO_ROOT } from '../lib/rig.mjs';
import { inRom } from '../lib/boot-rom.mjs';
import { UsbTimeout } from '../lib/usb-host.mjs';
import {
  decodeFeature,
  encodeEnterBootloader,
  encodeSelect,
  encodeSettings,
  FEATURE_KIND,
  FEATURE_REPORT_LEN,
  RESET_REASON,
  STATUS,
} from '../lib/reports.mjs';

const DEFAULT_PORT = { axialIsY: false, invertAxial: false, invertRotation: false, resolutionCode: 3, sampleRate: 200 };
/** The settings loop: a write from the host every 50 ms for 10 s (the store's own test
 *  runs the schedule for a minute from every fill level of a sector). */
const LOOP_S = 10;
const LOOP_PERIOD_US = 50_000;
/** Port 4 as the test sets it: axial = mouse y, rotation = -x, 4 counts/mm, 100/s. */
const PORT4 = { axialIsY: true, invertAxial: false, invertRotation: true, resolutionCode: 2, sampleRate: 100 };

function firmwareVersion() {
  const toml = readFileSync(join(REPO_ROOT, 'firmware', 'rp2040', 'Cargo.toml'), 'utf8');
  return toml.match(/^version\s*=\s*"(\d+)\.(\d+)\.(\d+)"/m).slice(1, 4).map(Number);
}

/** Boots a rig, enumerates, and runs until all eight mice are present. */
function bootedRig(options = {}) {
  const rig = createRig({ uf2Path: firmwareUf2Path(), printLog: process.env.FITL_LOG !== '0', ...options });
  rig.host.enumerate();
  rig.host.startPolling();
  const allPresent = () => {
    const last = rig.reports(rig.host.inReports.length - 1)[0];
    return last && last.paddles.every((p) => p.status & STATUS.PRESENT);
  };
  assert.ok(rig.board.runUntil(allPresent, 500_000), 'all eight paddles PRESENT');
  return rig;
}

/** `flash` (a board's whole flash: the program) with its settings store (the last two
 *  4 KiB sectors of the 2 MiB flash) holding a first sector full of records of `ports`
 *  and a blank second one: the next save erases the second. Records as `sensor-board`'s
 *  store writes them: magic `SFS1`, sequence number, the 24 bytes of the settings,
 *  CRC-32 of those, 36 bytes each, 113 to a sector. */
function imageWithFullStoreSector(flash, ports) {
  const image = Uint8Array.from(flash);
  const base = 2 * 1024 * 1024 - 2 * 4096;
  image.fill(0xff, base, base + 2 * 4096);
  const fields = encodeSettings(ports).subarray(2, 26);
  for (let slot = 0; slot < Math.floor(4096 / 36); slot++) {
    const record = new Uint8Array(36);
    const view = new DataView(record.buffer);
    record.set([0x53, 0x46, 0x53, 0x31]);
    view.setUint32(4, slot, true);
    record.set(fields, 8);
    view.setUint32(32, crc32(record.subarray(0, 32)), true);
    image.set(record, base + slot * 36);
  }
  return image;
}

function read(host, kind, port = 0) {
  host.setFeatureReport(encodeSelect(kind, port));
  return decodeFeature(host.getFeatureReport(FEATURE_REPORT_LEN));
}

describe('Feature reports', () => {
  let rig;
  before(() => {
    rig = bootedRig();
  });

  it('reports the firmware version, git hash, reset reason, uptime and present ports', () => {
    const { board, host } = rig;
    // After a reset the device info is selected: no Select needed.
    const info = decodeFeature(host.getFeatureReport(FEATURE_REPORT_LEN));
    assert.equal(info.kind, 'deviceInfo');
    assert.deepEqual(info.firmwareVersion, firmwareVersion());
    assert.match(info.gitHash, /^([0-9a-f]{12}|unknown\?{5})$/);
    assert.equal(info.resetReason, RESET_REASON.POWER_ON);
    // The uptime is the board's clock, which starts with the emulation.
    assert.ok(Math.abs(info.uptimeUs - board.timeUs) < 2_000, `uptime ${info.uptimeUs} µs at ${board.timeUs} µs`);
    assert.equal(info.presentPorts, 0xff);
  });

  it('reports each port: present, its device id and its counters', () => {
    const { host, mice } = rig;
    for (let port = 0; port < 8; port++) {
      const diag = read(host, FEATURE_KIND.PORT_DIAGNOSTICS, port);
      assert.equal(diag.kind, 'portDiagnostics');
      assert.equal(diag.port, port);
      assert.equal(diag.present, true);
      assert.equal(diag.deviceId, 0, 'a standard PS/2 mouse');
      assert.equal(diag.counters.inits, 1);
      // Every byte the mouse sent was a frame the board received: the replies to
      // the five initialisation commands and the self-test's AA 00, at least.
      assert.ok(diag.counters.frames >= 7, `port ${port}: ${diag.counters.frames} frames`);
      assert.equal(diag.counters.parityErrors, 0);
      assert.equal(diag.counters.framingErrors, 0);
      assert.equal(diag.counters.dropped, 0);
      assert.ok(mice[port].streaming);
    }
  });

  it('rejects a malformed Feature report and keeps reporting', () => {
    const { board, host } = rig;
    const bad = encodeEnterBootloader();
    bad[3] = 0x58; // "BXOT": not the magic
    const before = host.inReports.length;
    assert.throws(() => host.setFeatureReport(bad), UsbTimeout, 'rejected (STALL)');
    assert.ok(board.runUntil(() => board.logMatching(/ignoring malformed Feature report/).length > 0, 2_000));
    assert.equal(board.rom.usbBoot, null, 'no restart');
    board.runUs(5_000);
    assert.ok(host.inReports.length >= before + 4, 'IN reports go on');
  });

  it('applies new settings: the mouse gets its sample rate and resolution, the axis map turns its motion', () => {
    const { board, host, mice } = rig;
    assert.deepEqual(read(host, FEATURE_KIND.SETTINGS).ports, Array(8).fill(DEFAULT_PORT));
    const mouse = mice[4];
    const commandsBefore = mouse.received.length;
    const ports = Array(8).fill(DEFAULT_PORT);
    ports[4] = PORT4;
    host.setFeatureReport(encodeSettings(ports));
    assert.ok(board.runUntil(() => mouse.commands(commandsBefore).length >= 5, 100_000), 'port 4 reconfigured');
    assert.deepEqual(mouse.commands(commandsBefore), [0xf3, 100, 0xe8, 2, 0xf4]);
    assert.equal(mouse.sampleRate, 100);
    assert.equal(mouse.resolution, 2);
    for (const other of [0, 1, 2, 3, 5, 6, 7]) {
      assert.equal(mice[other].sampleRate, 200, `port ${other} untouched`);
    }
    assert.deepEqual(read(host, FEATURE_KIND.SETTINGS).ports, ports);

    const from = host.inReports.length;
    mouse.move(150, -90);
    mice[3].move(150, -90);
    board.runUs(40_000);
    const totals = rig.reports(from).reduce(
      (sum, r) => sum.map((s, i) => ({ axial: s.axial + r.paddles[i].axial, rotation: s.rotation + r.paddles[i].rotation })),
      Array.from({ length: 8 }, () => ({ axial: 0, rotation: 0 })),
    );
    assert.deepEqual(totals[4], { axial: -90, rotation: -150 }, 'port 4: axial = y, rotation = -x');
    assert.deepEqual(totals[3], { axial: 150, rotation: -90 }, 'port 3: identity');
  });

  it('keeps the settings across a power cycle (written to flash with a CRC, once they stay put for 0.5 s)', () => {
    const { board } = rig;
    assert.ok(board.runUntil(() => board.logMatching(/settings written to flash/).length > 0, 1_000_000), 'written within 1 s');
    const erases = board.rom.flashOps.filter((op) => op.op === 'erase');
    const programs = board.rom.flashOps.filter((op) => op.op === 'program');
    assert.ok(programs.length >= 1, 'the settings were written');
    assert.ok(board.logMatching(/settings written to flash/).length > 0);
    assert.equal(board.watchdogResets, 0, 'no watchdog reset while writing flash');
    for (const op of [...erases, ...programs]) {
      // The store's two sectors at the end of the 2 MiB flash, clear of the program.
      assert.ok(op.offset >= 2 * 1024 * 1024 - 2 * 4096, `flash ${op.op} at 0x${op.offset.toString(16)}`);
    }
    const again = bootedRig({ flashImage: Uint8Array.from(board.rp.flash) });
    const ports = Array(8).fill(DEFAULT_PORT);
    ports[4] = PORT4;
    assert.deepEqual(read(again.host, FEATURE_KIND.SETTINGS).ports, ports);
    assert.deepEqual(again.mice[4].commands().slice(0, 6), [0xff, 0xf3, 100, 0xe8, 2, 0xf4], 'configured from the kept settings');
    assert.ok(again.board.logMatching(/settings loaded from flash/).length > 0);
    assert.equal(again.board.watchdogResets, 0);
  });

  it(`a host writing settings in a loop for ${LOOP_S} s: at most one flash write a second and one sector erase; the last settings are kept`, (t) => {
    const { board, host } = rig;
    const ops = (op) => board.rom.flashOps.filter((o) => o.op === op).length;
    const [erasesBefore, programsBefore] = [ops('erase'), ops('program')];
    const ports = Array(8).fill(DEFAULT_PORT);
    ports[4] = PORT4;
    const start = board.timeUs;
    for (let i = 0; board.timeUs - start < LOOP_S * 1e6; i++) {
      // Port 1's axial direction flipped every write: no PS/2 traffic, a new value each time.
      ports[1] = { ...DEFAULT_PORT, invertAxial: i % 2 === 1 };
      host.setFeatureReport(encodeSettings(ports));
      board.runUs(LOOP_PERIOD_US - ((board.timeUs - start) % LOOP_PERIOD_US));
    }
    board.runUs(6_000_000); // the last change reaches the flash
    const erases = ops('erase') - erasesBefore;
    const programs = ops('program') - programsBefore;
    t.diagnostic(`${LOOP_S * 1e6 / LOOP_PERIOD_US} writes from the host: ${programs} flash programs, ${erases} erases`);
    assert.ok(erases <= 1, `${erases} sector erases`);
    assert.ok(programs <= LOOP_S + 2, `${programs} flash programs (at most one a second)`);
    assert.deepEqual(read(host, FEATURE_KIND.SETTINGS).ports, ports);
    const again = bootedRig({ flashImage: Uint8Array.from(board.rp.flash) });
    assert.deepEqual(read(again.host, FEATURE_KIND.SETTINGS).ports, ports, 'the last settings written survive a power cycle');
  });

  it('eight mice streaming through ten settings saves and a 400 ms sector erase: no frame lost', (t) => {
    const streaming = bootedRig({ flashImage: imageWithFullStoreSector(rig.board.rp.flash, Array(8).fill(DEFAULT_PORT)) });
    const { board, host, mice } = streaming;
    // The datasheet's worst sector erase, with interrupts off.
    board.rom.eraseUsPerSector = 400_000;
    const ops = (op) => board.rom.flashOps.filter((o) => o.op === op);
    mice.forEach((m) => (m.packets = []));
    board.runUs(10_000);
    const from = host.inReports.length;
    const logFrom = board.log.length;
    const ports = Array(8).fill(DEFAULT_PORT);
    let streamed = 0;
    for (let save = 0; save < 10; save++) {
      // A new value each time (port 0's rotation direction: the mice move along x only,
      // so the sums do not depend on it).
      ports[0] = { ...DEFAULT_PORT, invertRotation: save % 2 === 0 };
      host.setFeatureReport(encodeSettings(ports));
      for (let ms = 0; ms < 1_100; ms++, streamed++) {
        mice.forEach((mouse, port) => mouse.move(1 + (port % 3), 0));
        board.runUs(1_000);
      }
    }
    board.runUs(20_000);
    const erases = ops('erase');
    const saves = board.logMatching(/settings written to flash/, logFrom).length;
    t.diagnostic(`${streamed} ms streamed; ${saves} saves, ${erases.length} erase(s) of ${board.rom.eraseUsPerSector / 1000} ms`);
    assert.equal(erases.length, 1, 'the first save erased the other sector');
    assert.equal(saves, 10, 'ten saves');
    assert.equal(board.watchdogResets, 0);
    assert.deepEqual(board.logMatching(/RX FIFO stalled/, logFrom), [], 'no receiver overflowed');
    const reports = streaming.reports(from);
    mice.forEach((mouse, port) => {
      const sent = mouse.packets.reduce((sum, p) => sum + p.dx, 0);
      const reported = reports.reduce((sum, r) => sum + r.paddles[port].axial, 0);
      assert.equal(reported, sent, `port ${port}: ${reported} counts reported of ${sent} sent`);
      assert.ok(reports.every((r) => r.paddles[port].status === STATUS.PRESENT), `port ${port}: present, no error flags`);
    });
  });

  it('writes settings not yet in flash before restarting into the bootloader', () => {
    const { board, host } = bootedRig();
    const ports = Array(8).fill(DEFAULT_PORT);
    ports[6] = { ...DEFAULT_PORT, invertRotation: true };
    const programsBefore = board.rom.flashOps.filter((o) => o.op === 'program').length;
    host.setFeatureReport(encodeSettings(ports));
    host.setFeatureReport(encodeEnterBootloader());
    assert.ok(board.runUntil(() => board.rom.usbBoot !== null, 1_000_000), 'reset_to_usb_boot entered');
    const programs = board.rom.flashOps.filter((o) => o.op === 'program');
    assert.ok(programs.length > programsBefore, 'the pending settings were written');
    assert.ok(programs[programs.length - 1].timeUs <= board.rom.usbBoot.timeUs, 'before the restart');
    const again = bootedRig({ flashImage: Uint8Array.from(board.rp.flash) });
    assert.deepEqual(read(again.host, FEATURE_KIND.SETTINGS).ports, ports);
  });

  it('without a host for 1 s (a power-only port) the firmware runs on: no watchdog reset', () => {
    const { board } = createRig({ uf2Path: firmwareUf2Path(), printLog: process.env.FITL_LOG !== '0' });
    board.runUs(1_000_000);
    assert.equal(board.watchdogResets, 0);
    assert.ok(board.logMatching(/sensors present \(bit = port\): 11111111/).length > 0, 'the mice came up');
  });

  it('two resets within 500 ms restart into the USB bootloader; one, or two 0.6 s apart, start the firmware', () => {
    /** A reset through the RUN pin `afterUs` into a run of `board`: SRAM and flash kept. */
    const resetAfter = (board, afterUs) => {
      board.runUs(afterUs);
      return createRig({
        uf2Path: firmwareUf2Path(),
        printLog: process.env.FITL_LOG !== '0',
        flashImage: Uint8Array.from(board.rp.flash),
        sramImage: Uint8Array.from(board.rp.sram),
      }).board;
    };
    const first = createRig({ uf2Path: firmwareUf2Path(), printLog: process.env.FITL_LOG !== '0' }).board;
    const quick = resetAfter(first, 200_000);
    quick.runUs(20_000);
    assert.notEqual(quick.rom.usbBoot, null, 'the second of two quick resets enters the bootloader');
    assert.ok(quick.logMatching(/reset twice within 500 ms/).length > 0);
    // After the bootloader, a single reset starts the firmware (the mark was wiped).
    const afterBootloader = resetAfter(quick, 1_000);
    afterBootloader.runUs(50_000);
    assert.equal(afterBootloader.rom.usbBoot, null, 'one reset after the bootloader: the firmware');
    const slow = resetAfter(createRig({ uf2Path: firmwareUf2Path(), printLog: process.env.FITL_LOG !== '0' }).board, 600_000);
    slow.runUs(50_000);
    assert.equal(slow.rom.usbBoot, null, 'two resets 0.6 s apart: the firmware');
    assert.ok(slow.logMatching(/USB IN endpoint|sensors present|Space Foosball sensor board starting/).length > 0);
  });

  it('restarts into the ROM USB bootloader on request', () => {
    const { board, host } = rig;
    host.setFeatureReport(encodeEnterBootloader());
    const at = board.timeUs;
    assert.ok(board.runUntil(() => board.rom.usbBoot !== null, 100_000), 'reset_to_usb_boot entered');
    const { gpioMask, disableMask, timeUs } = board.rom.usbBoot;
    assert.equal(gpioMask, 0, 'no activity LED');
    assert.equal(disableMask, 0, 'mass storage and PICOBOOT both on');
    assert.ok(timeUs - at < 50_000, `entered ${((timeUs - at) / 1000).toFixed(1)} ms after the request`);
    board.runUs(1_000);
    assert.ok(inRom(board.rp.core.PC), `PC 0x${(board.rp.core.PC >>> 0).toString(16)} in the boot ROM`);
    assert.ok(board.logMatching(/restarting into the USB bootloader/).length > 0);
  });
});
