// Report latency, measured from the wire: from the end of a mouse packet (its last
// bit left the wire) to the first IN report that contains it.
//
// Motion is scripted positive along mouse x, so each paddle's running axial sum
// over the IN reports only grows; a packet is contained in the first report at
// which that sum reaches the running sum of the mouse's packets up to and
// including it (axis map identity: axial = mouse x).

/**
 * Per packet of one mouse: when it ended on the wire and when the first report
 * containing it arrived (null if none did yet).
 * @param {{ dx: number, endUs: number }[]} packets  the mouse's packets, in order
 * @param {{ timeUs: number, paddles: { axial: number }[] }[]} reports  IN reports, in order
 * @param {number} paddle
 */
export function packetLatencies(packets, reports, paddle) {
  const out = [];
  let sent = 0;
  let received = 0;
  let r = 0;
  for (const packet of packets) {
    if (packet.dx <= 0) {
      throw new Error(`packet latency needs positive x motion, got dx ${packet.dx}`);
    }
    sent += packet.dx;
    while (r < reports.length && received < sent) {
      received += reports[r].paddles[paddle].axial;
      r++;
    }
    const report = received >= sent ? reports[r - 1] : null;
    out.push({ endUs: packet.endUs, reportUs: report ? report.timeUs : null, latencyUs: report ? report.timeUs - packet.endUs : null });
  }
  return out;
}

/**
 * Per report: how far it lags the wire — the age, at the report's arrival, of the
 * oldest packet that had ended on the wire but is not contained in it or an
 * earlier report (0 when it carries everything that had ended).
 */
export function reportStaleness(packets, reports, paddle) {
  const ends = [];
  let cumulative = 0;
  for (const p of packets) {
    cumulative += p.dx;
    ends.push({ cumulative, endUs: p.endUs });
  }
  const out = [];
  let received = 0;
  let k = 0;
  for (const report of reports) {
    received += report.paddles[paddle].axial;
    while (k < ends.length && ends[k].cumulative <= received) {
      k++;
    }
    // ends[k] is the oldest packet not yet contained.
    const missing = k < ends.length && ends[k].endUs <= report.timeUs ? report.timeUs - ends[k].endUs : 0;
    out.push({ timeUs: report.timeUs, sequence: report.sequence, staleUs: missing });
  }
  return out;
}

/** Worst, 99th percentile, median and count of a list of numbers. */
export function summary(values) {
  const sorted = [...values].sort((a, b) => a - b);
  const at = (q) => (sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))] : null);
  return {
    count: sorted.length,
    worst: sorted.length ? sorted[sorted.length - 1] : null,
    p99: at(0.99),
    median: at(0.5),
  };
}
