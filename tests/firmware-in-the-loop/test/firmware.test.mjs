// Firmware in the loop: the release firmware ELF on an emulated RP2040 with eight
// PS/2 mice on its GPIOs and a USB host. The tests run in order on one emulation
// (each continues from the state the previous one left).
import { before, describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { createRig, firmwareUf2Path, HAPTIC_GPIO, LED_GPIO, REPO_ROOT } from '../lib/rig.mjs';
import { DEFAULT_UNIQUE_ID } from '../lib/board.mjs';
import {
  encodeOutReport,
  FORMAT_VERSION,
  HID_REPORT_DESCRIPTOR,
  IN_FORMAT_VERSION,
  IN_REPORT_LEN,
  LED,
  OUT_REPORT_LEN,
  PADDLES,
  STATUS,
  USB_IDS,
} from '../lib/reports.mjs';

const INIT_SEQUENCE = [0xff, 0xf3, 200, 0xe8, 0x03, 0xf4];

/** The firmware crate's version (firmware/rp2040/Cargo.toml) and its bcdDevice. */
function firmwareVersion() {
  const toml = readFileSync(join(REPO_ROOT, 'firmware', 'rp2040', 'Cargo.toml'), 'utf8');
  const text = /^version\s*=\s*"(\d+)\.(\d+)\.(\d+)"/m.exec(toml);
  assert.ok(text, 'a version in firmware/rp2040/Cargo.toml');
  const [major, minor, patch] = text.slice(1).map(Number);
  const bcd = (Math.floor(major / 10) << 12) | (major % 10 << 8) | (minor << 4) | patch;
  return { text: text.slice(1).join('.'), bcd };
}
const CONFIG_SEQUENCE = INIT_SEQUENCE.slice(1);

/** Whether `needle` occurs in `haystack` as a contiguous run. */
function containsRun(haystack, needle) {
  for (let i = 0; i + needle.length <= haystack.length; i++) {
    if (needle.every((b, j) => haystack[i + j] === b)) {
      return true;
    }
  }
  return false;
}

const hex = (bytes) => bytes.map((b) => b.toString(16).padStart(2, '0')).join(' ');

/** Sums of axial / rotation per paddle and the OR of the status bits over reports. */
function sums(reports) {
  const out = Array.from({ length: PADDLES }, () => ({ axial: 0, rotation: 0, status: 0 }));
  for (const report of reports) {
    report.paddles.forEach((p, i) => {
      out[i].axial += p.axial;
      out[i].rotation += p.rotation;
      out[i].status |= p.status;
    });
  }
  return out;
}

/** The pulse on a PWM pin from its recorded edges (after index `since`). */
function pulse(edges, since) {
  const seen = edges.slice(since);
  const rising = seen.filter((e) => e.high);
  const falling = seen.filter((e) => !e.high);
  if (rising.length === 0) {
    return null;
  }
  const start = rising[0].timeNs;
  const end = falling.length ? falling[falling.length - 1].timeNs : Infinity;
  let highNs = 0;
  for (let i = 0; i < seen.length; i++) {
    if (seen[i].high) {
      const next = seen[i + 1] ? seen[i + 1].timeNs : end;
      highNs += next - seen[i].timeNs;
    }
  }
  return { startMs: start / 1e6, durationMs: (end - start) / 1e6, duty: highNs / (end - start) };
}

describe('firmware in the loop', () => {
  let rig;
  let board;
  let mice;
  let host;

  before(() => {
    // Booted from the UF2 a builder flashes, not from the ELF's segments.
    rig = createRig({ uf2Path: firmwareUf2Path() });
    ({ board, mice, host } = rig);
  });

  it('enumerates over USB as the sensor board (descriptors, address, configuration, HID report descriptor)', () => {
    const info = host.enumerate();
    assert.equal(info.vendorId, USB_IDS.vendorId);
    assert.equal(info.productId, USB_IDS.productId);
    const version = firmwareVersion();
    assert.equal(info.bcdDevice, version.bcd, `bcdDevice 0x${info.bcdDevice.toString(16)} for version ${version.text}`);
    assert.equal(info.bcdUSB, 0x0200);
    assert.equal(info.maxPacket0, 64);
    assert.equal(info.manufacturer, USB_IDS.manufacturer);
    assert.equal(info.product, USB_IDS.product);
    // The serial number is the flash chip's unique id (the emulated chip's, answering
    // command 0x4B), 16 upper-case hex digits.
    assert.match(info.serial ?? '', /^[0-9A-F]{16}$/);
    assert.equal(info.serial, Buffer.from(DEFAULT_UNIQUE_ID).toString('hex').toUpperCase());
    assert.equal(info.maxPowerMa, 100);
    assert.equal(info.hid.class, 3);
    assert.equal(info.hid.reportDescriptorLength, HID_REPORT_DESCRIPTOR.length);
    assert.deepEqual([...info.reportDescriptor], [...HID_REPORT_DESCRIPTOR]);
    const interruptEndpoints = info.hid.endpoints.filter((e) => (e.attributes & 3) === 3);
    assert.equal(interruptEndpoints.length, 2, 'one interrupt IN and one interrupt OUT endpoint');
    for (const ep of interruptEndpoints) {
      assert.equal(ep.maxPacket, 64);
      assert.equal(ep.interval, 1);
    }
    host.startPolling();
  });

  it('initialises all eight mice (reset, sample rate 200, resolution 8/mm, enable) and reports them present', () => {
    const allPresent = () => {
      const last = rig.reports(host.inReports.length - 1)[0];
      return last && last.paddles.every((p) => p.status & STATUS.PRESENT);
    };
    assert.ok(board.runUntil(allPresent, 500_000), 'all eight paddles PRESENT within 0.5 s');
    for (const mouse of mice) {
      const commands = mouse.commands();
      assert.deepEqual(
        commands.slice(0, INIT_SEQUENCE.length),
        INIT_SEQUENCE,
        `port ${mouse.port} got ${hex(commands)}`,
      );
      assert.ok(mouse.received.every((r) => r.parityOk), `port ${mouse.port}: a command with bad parity`);
      const inhibits = mouse.received.map((r) => r.inhibitUs);
      assert.ok(
        inhibits.every((us) => us >= 100 && us <= 200),
        `port ${mouse.port}: request-to-send holds the clock low ${inhibits.join(', ')} µs (spec: ≥ 100)`,
      );
      assert.equal(mouse.streaming, true);
      assert.equal(mouse.sampleRate, 200);
      assert.equal(mouse.resolution, 3);
    }
    assert.ok(board.logMatching(/sensors present \(bit = port\): 11111111/).length > 0, 'firmware logs all present');
    const flagged = sums(rig.reports());
    flagged.forEach((p, i) => assert.ok(p.status & STATUS.REINITIALISED, `paddle ${i} REINITIALISED once`));
  });

  it('sends a 63-byte version 2 IN report every 1 ms frame with consecutive sequence numbers and the device time', () => {
    const from = host.inReports.length;
    const frame0 = host.frame;
    board.runUs(50_000);
    const received = host.inReports.slice(from);
    const frames = host.frame - frame0;
    assert.ok(received.length >= frames - 1 && received.length <= frames, `${received.length} reports in ${frames} frames`);
    const reports = rig.reports(from);
    for (const [i, r] of reports.entries()) {
      assert.equal(received[i].data.length, IN_REPORT_LEN);
      assert.equal(r.version, IN_FORMAT_VERSION);
      if (i > 0) {
        assert.equal(r.sequence, (reports[i - 1].sequence + 1) & 0xffff, 'no report lost');
        // One snapshot per 1 ms polling period, on the board's clock.
        const step = r.deviceTimeUs - reports[i - 1].deviceTimeUs;
        assert.ok(step >= 900 && step <= 1100, `device time step ${step} µs`);
      }
      // The board's clock starts with the emulation: the snapshot is taken shortly
      // before the host's IN token (the firmware's 150 µs lead, plus the transfer).
      const lead = r.timeUs - r.deviceTimeUs;
      assert.ok(lead >= 0 && lead <= 300, `snapshot ${lead.toFixed(0)} µs before the report arrived`);
      r.paddles.forEach((p) => assert.equal(p.status, STATUS.PRESENT, 'present, no error flags'));
      r.paddles.forEach((p) => assert.equal(p.dropped, 0, 'nothing dropped'));
    }
  });

  it('delivers scripted motion on each mouse to its paddle, summed exactly (axis map: axial = x, rotation = y)', () => {
    const script = mice.map((_, p) => ({
      dx: (p % 2 ? -1 : 1) * (40 + 97 * p), // up to 719: several packets per move
      dy: ((p % 3) - 1) * (25 + 61 * p),
    }));
    const from = host.inReports.length;
    // Three moves per mouse, 7 ms apart: 3/7, 2/7 and the rest.
    const parts = [3 / 7, 2 / 7, 2 / 7];
    const done = mice.map(() => ({ dx: 0, dy: 0 }));
    parts.forEach((fraction, k) => {
      mice.forEach((mouse, p) => {
        const last = k === parts.length - 1;
        const dx = last ? script[p].dx - done[p].dx : Math.trunc(script[p].dx * fraction);
        const dy = last ? script[p].dy - done[p].dy : Math.trunc(script[p].dy * fraction);
        done[p].dx += dx;
        done[p].dy += dy;
        mouse.move(dx, dy);
      });
      board.runUs(7_000);
    });
    board.runUs(40_000);
    // A report that carries a new packet says how old it was at the snapshot: less
    // than the time since the previous report (the packet came after that one).
    for (const r of rig.reports(from)) {
      r.paddles.forEach((p, i) => {
        if (p.axial !== 0 || p.rotation !== 0) {
          assert.notEqual(p.newestPacketAgeUs, null, `paddle ${i}: a packet age`);
          assert.ok(p.newestPacketAgeUs < 1_100, `paddle ${i}: packet ${p.newestPacketAgeUs} µs old`);
        }
      });
    }
    const totals = sums(rig.reports(from));
    mice.forEach((mouse, p) => {
      assert.deepEqual(mouse.takeSentMotion(), script[p], `mouse ${p} sent its script`);
      assert.equal(totals[p].axial, script[p].dx, `paddle ${p} axial`);
      assert.equal(totals[p].rotation, script[p].dy, `paddle ${p} rotation`);
      assert.equal(totals[p].status, STATUS.PRESENT, `paddle ${p}: no error or overflow flags`);
    });
  });

  it('reports an unplugged mouse absent within 100 ms, the others unaffected, and re-initialises it when replugged', (t) => {
    const port = 3;
    const mouse = mice[port];
    const from = host.inReports.length;
    const unpluggedAt = board.timeUs;
    mouse.unplug();
    const absent = () => {
      const last = rig.reports(host.inReports.length - 1)[0];
      return last && !(last.paddles[port].status & STATUS.PRESENT);
    };
    assert.ok(board.runUntil(absent, 200_000), 'paddle reported absent');
    const absentAfterMs = (board.timeUs - unpluggedAt) / 1000;
    assert.ok(absentAfterMs <= 100, `absent after ${absentAfterMs.toFixed(1)} ms`);
    t.diagnostic(`port ${port} reported absent ${absentAfterMs.toFixed(1)} ms after the unplug`);
    for (const r of rig.reports(from)) {
      r.paddles.forEach((p, i) => {
        if (i !== port) {
          assert.ok(p.status & STATUS.PRESENT, `paddle ${i} stays present`);
        }
      });
    }
    // The log line comes from the sensor loop's next pass, the report from the
    // snapshot: allow one millisecond between them.
    assert.ok(board.runUntil(() => board.logMatching(/sensors present \(bit = port\): 11110111/).length > 0, 1000));
    board.runUs(100_000); // stays absent while unplugged (resets go unanswered)
    assert.ok(absent());

    const commandsBefore = mouse.received.length;
    const replugFrom = host.inReports.length;
    const pluggedAt = board.timeUs;
    mouse.plug();
    const back = () => {
      const last = rig.reports(host.inReports.length - 1)[0];
      return last && last.paddles[port].status & STATUS.PRESENT;
    };
    assert.ok(board.runUntil(back, 500_000), 'paddle present again');
    const again = mouse.commands(commandsBefore);
    assert.ok(containsRun(again, CONFIG_SEQUENCE), `re-initialised: ${hex(again)}`);
    t.diagnostic(`after the replug port ${port} got ${hex(again)}; present again ${((board.timeUs - pluggedAt) / 1000).toFixed(1)} ms after it`);
    assert.ok(sums(rig.reports(replugFrom))[port].status & STATUS.REINITIALISED, 'REINITIALISED flag');
    assert.ok(board.runUntil(() => board.logMatching(/sensors present \(bit = port\): 11111111/, 0).length >= 2, 1000));

    // And its motion arrives again.
    const motionFrom = host.inReports.length;
    mouse.move(-77, 33);
    board.runUs(30_000);
    const totals = sums(rig.reports(motionFrom));
    assert.equal(totals[port].axial, -77);
    assert.equal(totals[port].rotation, 33);
  });

  it('ignores malformed OUT reports (wrong length, unknown version) and keeps reporting', () => {
    const logFrom = board.log.length;
    const reportFrom = host.inReports.length;
    const edgesFrom = rig.haptics.map((e) => e.length);
    const strong = Array.from({ length: PADDLES }, () => ({ strength: 255, durationMs: 40 }));
    host.sendOut(encodeOutReport(strong).subarray(0, OUT_REPORT_LEN - 1)); // 17 bytes
    host.sendOut([...encodeOutReport(strong), 0]); // 19 bytes
    host.sendOut(encodeOutReport(strong, LED.ON, FORMAT_VERSION + 1)); // version 2
    board.runUs(60_000);
    assert.equal(host.outQueue.length, 0, 'all three OUT reports taken by the device');
    const warnings = board.logMatching(/ignoring malformed OUT report/, logFrom);
    assert.equal(warnings.length, 3, warnings.map((w) => w.text).join('\n'));
    assert.match(warnings[0].text, /WrongLength \{ expected: 18, actual: 17 \}/);
    assert.match(warnings[1].text, /WrongLength \{ expected: 18, actual: 19 \}/);
    assert.match(warnings[2].text, /UnknownVersion \{ found: 2, supported: 1 \}/);
    rig.haptics.forEach((edges, i) => assert.equal(edges.length, edgesFrom[i], `motor ${i} stays off`));
    const reports = rig.reports(reportFrom);
    assert.ok(reports.length >= 55, `${reports.length} IN reports in 60 ms`);
    reports.forEach((r, i) => i && assert.equal(r.sequence, (reports[i - 1].sequence + 1) & 0xffff));
  });

  const pulses = [
    { motor: 5, strength: 200, durationMs: 30 },
    { motor: 7, strength: 255, durationMs: 45 },
    { motor: 0, strength: 64, durationMs: 20 },
  ];
  for (const { motor, strength, durationMs } of pulses) {
    it(`turns a valid OUT report into a ${durationMs} ms PWM pulse at ${strength}/255 on motor ${motor} (GPIO ${HAPTIC_GPIO[motor]})`, (t) => {
      const edgesFrom = rig.haptics.map((e) => e.length);
      const reportFrom = host.inReports.length;
      const request = [];
      request[motor] = { strength, durationMs };
      host.sendOut(encodeOutReport(request, LED.ON));
      const sentFrom = host.outSent.length;
      board.runUs((durationMs + 30) * 1000);
      assert.equal(host.outSent.length, sentFrom + 1);
      const measured = pulse(rig.haptics[motor], edgesFrom[motor]);
      assert.ok(measured, 'a pulse on the pin');
      t.diagnostic(
        `GPIO ${HAPTIC_GPIO[motor]}: pulse ${measured.durationMs.toFixed(3)} ms, duty ${measured.duty.toFixed(3)}, ` +
          `${rig.haptics[motor].length - edgesFrom[motor]} edges`,
      );
      assert.ok(
        Math.abs(measured.durationMs - durationMs) <= 1,
        `pulse of ${measured.durationMs.toFixed(3)} ms, requested ${durationMs} ms`,
      );
      const latencyMs = measured.startMs - host.outSent[sentFrom].timeUs / 1000;
      t.diagnostic(`pulse starts ${(latencyMs * 1000).toFixed(0)} µs after the OUT transfer`);
      assert.ok(latencyMs < 1, `starts ${latencyMs.toFixed(3)} ms after the OUT transfer`);
      assert.ok(Math.abs(measured.duty - strength / 255) < 0.02, `duty ${measured.duty.toFixed(3)}`);
      rig.haptics.forEach((edges, i) => {
        if (i !== motor) {
          assert.equal(edges.length, edgesFrom[i], `motor ${i} stays off`);
        }
      });
      const reports = rig.reports(reportFrom);
      assert.ok(reports.length >= durationMs + 25, 'reporting goes on');
    });
  }

  it('stops a running motor and the LED when the host suspends the bus, and reports again after resume', (t) => {
    const motor = 2;
    const pin = HAPTIC_GPIO[motor];
    const request = [];
    request[motor] = { strength: 255, durationMs: 300 };
    host.sendOut(encodeOutReport(request, LED.ON));
    board.runUs(20_000);
    assert.equal(board.rp.gpio[pin].outputValue, true, `motor ${motor} running`);
    assert.equal(board.rp.gpio[LED_GPIO].outputValue, true, 'LED on');
    const suspendedAt = board.timeUs;
    host.suspend();
    const stopped = () => !board.rp.gpio[pin].outputValue && !board.rp.gpio[LED_GPIO].outputValue;
    // The USB spec gives a suspended device 10 ms to get down to suspend current.
    assert.ok(board.runUntil(stopped, 10_000, 10), 'motor and LED off after the suspend');
    const stoppedAfterUs = board.timeUs - suspendedAt;
    t.diagnostic(`motor ${motor} and LED off ${stoppedAfterUs.toFixed(0)} µs after the suspend`);
    const edges = rig.haptics[motor].length;
    board.runUs(50_000);
    assert.equal(rig.haptics[motor].length, edges, 'the motor stays off while suspended');
    assert.equal(board.rp.gpio[LED_GPIO].outputValue, false, 'LED stays off');
    assert.ok(board.logMatching(/USB suspended: motors and LED off/).length > 0);

    const reportFrom = host.inReports.length;
    host.resume();
    board.runUs(30_000);
    const reports = rig.reports(reportFrom);
    assert.ok(reports.length >= 25, `${reports.length} IN reports in 30 ms after resume`);
    reports.forEach((r, i) => i && assert.equal(r.sequence, (reports[i - 1].sequence + 1) & 0xffff));
    assert.equal(rig.haptics[motor].length, edges, 'the pulse does not come back after resume');
  });

  it('reports again after a bus reset and a new enumeration, motion intact', () => {
    const logFrom = board.log.length;
    const mouse = mice[1];
    mouse.move(40, 0);
    board.runUs(3_000); // the packet is in the board, maybe not yet reported
    const info = host.reenumerate();
    assert.equal(info.productId, USB_IDS.productId);
    const from = host.inReports.length;
    host.startPolling();
    board.runUs(30_000);
    const reports = rig.reports(from);
    assert.ok(reports.length >= 25, `${reports.length} IN reports in 30 ms after the new enumeration`);
    reports.forEach((r, i) => i && assert.equal(r.sequence, (reports[i - 1].sequence + 1) & 0xffff));
    assert.ok(board.logMatching(/USB bus reset: motors stopped/, logFrom).length > 0);
    const motionFrom = host.inReports.length;
    mouse.move(-25, 9);
    board.runUs(30_000);
    const totals = sums(rig.reports(motionFrom));
    assert.deepEqual([totals[1].axial, totals[1].rotation], [-25, 9]);
  });

  it('ran without a watchdog reset, a panic or a decode error', () => {
    assert.equal(board.bootedFrom, firmwareUf2Path(), 'booted from the UF2');
    assert.equal(board.watchdogResets, 0);
    const errors = board.log.filter((m) => m.level === 'ERROR');
    assert.deepEqual(errors, []);
    console.log(`emulated ${(board.timeUs / 1000).toFixed(1)} ms`);
  });
});
