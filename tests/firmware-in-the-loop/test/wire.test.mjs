// Realistic mice and faults on the wire, on its own emulation: PS/2 clocks from
// 10 to 16.7 kHz, 10–15 ms to answer request-to-send, replies up to 20 ms, self-tests
// from 20 ms to 2.5 s (the PS/2 limits), then a quick restart whose 0xAA is lost and
// 1 % parity errors on every mouse.
import { before, describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { createRig } from '../lib/rig.mjs';
import { STATUS } from '../lib/reports.mjs';

const CONFIG_SEQUENCE = [0xf3, 200, 0xe8, 0x03, 0xf4];

/** Per port: clock 10–16.7 kHz, 10–15 ms to start clocking after request-to-send,
 *  replies 5–20 ms, self-tests 20 ms–2.5 s. */
function slowMouse(port) {
  return {
    halfPeriodUs: 30 + (20 * port) / 7,
    rtsDelayUs: 10_000 + (5_000 * port) / 7,
    replyDelayUs: 5_000 + (15_000 * ((port * 3) % 8)) / 7,
    selfTestUs: [20_000, 2_500_000, 300_000, 500_000, 1_000_000, 50_000, 1_500_000, 100_000][port],
    seed: 0x9e3779b9 ^ (port * 0x85ebca6b),
  };
}

function containsRun(haystack, needle) {
  for (let i = 0; i + needle.length <= haystack.length; i++) {
    if (needle.every((b, j) => haystack[i + j] === b)) {
      return true;
    }
  }
  return false;
}

describe('realistic mice on the wire', () => {
  let rig;
  const lastReport = () => rig.reports(rig.host.inReports.length - 1)[0];

  before(() => {
    rig = createRig({ mouse: slowMouse });
    rig.host.enumerate();
    rig.host.startPolling();
  });

  it('slow but compliant mice (15 ms to clock, 20 ms replies, 2.5 s self-test) come up and stay present', (t) => {
    const { board, mice } = rig;
    const allPresent = () => lastReport()?.paddles.every((p) => p.status & STATUS.PRESENT);
    assert.ok(board.runUntil(allPresent, 4_000_000), 'all eight PRESENT within 4 s (self-tests up to 2.5 s)');
    t.diagnostic(`all present at ${(board.timeUs / 1000).toFixed(0)} ms`);
    const from = rig.host.inReports.length;
    // 600 ms idle: the driver probes every 30 ms of silence; each probe takes the
    // slow mice up to 15 + 1 + 20 ms to answer.
    board.runUs(600_000);
    const reports = rig.reports(from);
    for (const r of reports) {
      r.paddles.forEach((p, i) => assert.ok(p.status & STATUS.PRESENT, `paddle ${i} stays present`));
    }
    const probes = mice.map((m) => m.commands().filter((b) => b === 0xe9).length);
    t.diagnostic(`status probes per mouse: ${probes.join(', ')}`);
    probes.forEach((n, i) => assert.ok(n >= 5, `mouse ${i} probed ${n} times`));
    assert.ok(board.logMatching(/sensors present \(bit = port\): 11111111/).length === 1, 'no port ever dropped out');
  });

  it('a quick restart whose 0xAA is lost is detected and re-initialisation under way within 100 ms', (t) => {
    const { board, mice } = rig;
    const port = 0; // 20 ms self-test, 10 ms to clock, 5 ms replies
    const mouse = mice[port];
    const commandsFrom = mouse.received.length;
    const reportFrom = rig.host.inReports.length;
    const restartedAt = board.timeUs;
    mouse.restart({ loseSelfTestByte: true });
    // Detected: the configuration starts again (the status request showed the
    // power-on defaults).
    const reconfiguring = () => mouse.commands(commandsFrom).includes(0xf3);
    assert.ok(board.runUntil(reconfiguring, 100_000, 100), `re-initialising within 100 ms: got ${mouse.commands(commandsFrom)}`);
    const detectedMs = (board.timeUs - restartedAt) / 1000;
    // Then five commands, each at most 15 ms to clock + 1.1 ms frame + 20 ms reply.
    const configured = () => mouse.streaming && mouse.sampleRate === 200 && mouse.resolution === 3;
    assert.ok(board.runUntil(configured, 5 * 36_100, 100), `configured: got ${mouse.commands(commandsFrom)}`);
    const configuredMs = (board.timeUs - restartedAt) / 1000;
    t.diagnostic(
      `mouse ${port}: re-initialisation started ${detectedMs.toFixed(1)} ms after the restart, ` +
        `streaming at its settings again after ${configuredMs.toFixed(1)} ms`,
    );
    assert.ok(containsRun(mouse.commands(commandsFrom), CONFIG_SEQUENCE));
    board.runUs(40_000);
    const flagged = rig.reports(reportFrom).some((r) => r.paddles[port].status & STATUS.REINITIALISED);
    assert.ok(flagged, 'REINITIALISED reported');
    assert.ok(lastReport().paddles[port].status & STATUS.PRESENT);
    // Its motion arrives at full resolution.
    const motionFrom = rig.host.inReports.length;
    mouse.move(120, -40);
    board.runUs(30_000);
    const sum = rig.reports(motionFrom).reduce((s, r) => s + r.paddles[port].axial, 0);
    assert.equal(sum, 120);
  });

  it('clock glitches and 1 % parity errors on every mouse lose less than one packet of motion per fault', (t) => {
    const { board, mice } = rig;
    mice.forEach((m) => {
      m.parityErrorRate = 0.01;
      m.parityErrorsSent = 0;
      // And a 2 µs low pulse on the clock in 1 % of the frames.
      m.clockGlitchRate = 0.01;
      m.clockGlitchesSent = 0;
      m.takeSentMotion();
    });
    const from = rig.host.inReports.length;
    // 3 s of every mouse moving 1 + port counts per ms in x: a packet every 5 ms.
    for (let ms = 0; ms < 3000; ms++) {
      mice.forEach((m, port) => m.move(1 + port, 0));
      board.runUs(1000);
    }
    mice.forEach((m) => {
      m.parityErrorRate = 0;
      m.clockGlitchRate = 0;
    });
    board.runUs(100_000);
    const reports = rig.reports(from);
    let faults = 0;
    let glitches = 0;
    mice.forEach((mouse, port) => {
      const sent = mouse.takeSentMotion().dx;
      const received = reports.reduce((s, r) => s + r.paddles[port].axial, 0);
      const lost = sent - received;
      const packet = 5 * (1 + port);
      const mouseFaults = mouse.parityErrorsSent + mouse.clockGlitchesSent;
      faults += mouse.parityErrorsSent;
      glitches += mouse.clockGlitchesSent;
      t.diagnostic(
        `mouse ${port}: ${mouse.parityErrorsSent} parity errors, ${mouse.clockGlitchesSent} clock glitches, ` +
          `${sent} counts sent, ${lost} lost (a packet: ${packet})`,
      );
      assert.ok(received <= sent, `mouse ${port}: more motion reported than sent`);
      assert.ok(lost < Math.max(1, mouseFaults) * packet, `mouse ${port}: ${lost} counts lost to ${mouseFaults} faults`);
      assert.ok(reports.every((r) => r.paddles[port].status & STATUS.PRESENT), `paddle ${port} stays present`);
    });
    assert.ok(faults >= 50, `${faults} parity errors injected`);
    assert.ok(glitches >= 50, `${glitches} clock glitches injected`);
    // The receiver ignores the glitches: no frame is garbled by one, so the only
    // framing errors are none (a glitch that got through would shift a frame).
    const framing = reports.filter((r) => r.paddles.some((p) => p.status & STATUS.FRAMING_ERROR)).length;
    assert.equal(framing, 0, 'no frame garbled by a glitch');
    const flagged = reports.filter((r) => r.paddles.some((p) => p.status & STATUS.PARITY_ERROR)).length;
    assert.ok(flagged > 0, 'parity errors are flagged');
  });

  it('frames that arrive while the CPU is held wait in the receive ring: none lost, nothing stalls', (t) => {
    const { board, mice } = rig;
    const port = 5;
    const mouse = mice[port];
    const logFrom = board.log.length;
    const reportFrom = rig.host.inReports.length;
    // The mouse sends two packets back to back (six frames, ≈ 6 ms at its clock) while
    // the CPU is held for 80 ms (a flash erase with interrupts off, within the
    // watchdog's 100 ms): the 4-word RX FIFO alone would overflow and stall.
    mouse.move(255, 0);
    mouse.move(255, 0);
    board.holdCpu(80_000);
    board.runUs(120_000);
    assert.deepEqual(board.logMatching(/RX FIFO stalled/, logFrom), [], 'no receiver stalled');
    const reports = rig.reports(reportFrom);
    assert.ok(reports.every((r) => r.paddles[port].status === STATUS.PRESENT), 'present, no error flags');
    const held = reports.reduce((s, r) => s + r.paddles[port].axial, 0);
    t.diagnostic(`${held} of the 510 counts sent during the hold arrived`);
    assert.equal(held, 510);
    assert.equal(board.watchdogResets, 0);
  });

  it('a line stuck low is reported as a wiring fault, not as an unplugged mouse', (t) => {
    const { board, mice } = rig;
    const logFrom = board.log.length;
    const reportFrom = rig.host.inReports.length;
    // Port 6: its clock line shorted to ground; port 7: its data line.
    mice[6].unplug();
    board.setDeviceLow(mice[6].clockPin, true);
    mice[7].unplug();
    board.setDeviceLow(mice[7].dataPin, true);
    const at = board.timeUs;
    const seen = (re) => board.logMatching(re, logFrom).length > 0;
    const both = () => seen(/port 6: clock line stuck low/) && seen(/port 7: data line stuck low/);
    assert.ok(board.runUntil(both, 1_000_000), 'both faults logged within 1 s');
    t.diagnostic(`both line faults logged ${((board.timeUs - at) / 1000).toFixed(0)} ms after the short`);
    const last = lastReport();
    assert.ok(!(last.paddles[6].status & STATUS.PRESENT) && !(last.paddles[7].status & STATUS.PRESENT));
    rig.reports(reportFrom).forEach((r) =>
      r.paddles.slice(0, 6).forEach((p, i) => assert.ok(p.status & STATUS.PRESENT, `paddle ${i} unaffected`)),
    );
    assert.equal(board.logMatching(/port [0-5]: .*stuck low/, logFrom).length, 0, 'no other port reported');
    // Repaired: the lines come free and the mice are found again.
    board.setDeviceLow(mice[6].clockPin, false);
    board.setDeviceLow(mice[7].dataPin, false);
    mice[6].plug();
    mice[7].plug();
    const back = () => [6, 7].every((p) => lastReport().paddles[p].status & STATUS.PRESENT);
    // Port 6's self-test takes 1.5 s.
    assert.ok(board.runUntil(back, 2_500_000), 'both ports present again');
    assert.ok(seen(/port 6: lines free again/) && seen(/port 7: lines free again/));
  });
});
