// The page's glue: loads the game (wasm), and moves WebHID reports between the sensor
// board and the game. The reports are decoded by the protocol crate inside the wasm
// module; this file only moves bytes.
//
// `?hid=fake` replaces navigator.hid by a scripted device (window.fakeHid) that the
// browser test drives: its `input(bytes)` dispatches an `inputreport` event exactly as
// a real device does, its `sent` lists the OUT reports the game sent.
//
// `?pad=fake` replaces navigator.getGamepads by one scripted gamepad of the standard
// mapping (window.fakePad), whose `axes` and `buttons` the browser test sets; the game
// reads it through gilrs's Gamepad API backend as it would a real one.
import init, * as game from "./pkg/space_foosball_web.js";

const params = new URLSearchParams(location.search);
const boardLabel = document.getElementById("board");
const message = document.getElementById("message");

class FakeHidDevice extends EventTarget {
  constructor(vendorId, productId) {
    super();
    this.vendorId = vendorId;
    this.productId = productId;
    this.productName = "scripted board";
    this.opened = false;
    this.sent = [];
  }
  async open() { this.opened = true; }
  async close() { this.opened = false; }
  async sendReport(reportId, data) {
    this.sent.push({ reportId, bytes: Array.from(new Uint8Array(data.buffer ?? data)) });
  }
  input(bytes) {
    const data = new DataView(new Uint8Array(bytes).buffer);
    const event = new Event("inputreport");
    event.device = this;
    event.reportId = 0;
    event.data = data;
    this.dispatchEvent(event);
  }
}

class FakeHid extends EventTarget {
  constructor(device) { super(); this.device = device; }
  async getDevices() { return []; }
  async requestDevice() { return [this.device]; }
  disconnect() {
    const event = new Event("disconnect");
    event.device = this.device;
    this.dispatchEvent(event);
  }
  connect() {
    const event = new Event("connect");
    event.device = this.device;
    this.dispatchEvent(event);
  }
}

if (params.get("pad") === "fake") {
  const pad = {
    id: "scripted gamepad",
    index: 0,
    connected: true,
    mapping: "standard",
    timestamp: 0,
    axes: [0, 0, 0, 0],
    buttons: Array.from({ length: 17 }, () => ({ pressed: false, touched: false, value: 0 })),
  };
  window.fakePad = pad;
  Object.defineProperty(navigator, "getGamepads", { value: () => [pad, null, null, null] });
}

let current = null;
let lost = false;
let pump = null;

function sendOutReports(device) {
  for (let r = game.take_out_report(); r !== undefined; r = game.take_out_report()) {
    device.sendReport(0, r).catch((e) => console.warn("space-foosball: OUT report not sent:", e));
  }
}

async function attach(device) {
  if (!device.opened) await device.open();
  if (current !== device) {
    device.addEventListener("inputreport", (e) => {
      game.hid_report(new Uint8Array(e.data.buffer, e.data.byteOffset, e.data.byteLength));
    });
  }
  current = device;
  lost = false;
  game.hid_opened(device.productName || "");
  boardLabel.textContent = `Board: ${device.productName || "sensor board"}`;
  if (pump === null) pump = setInterval(() => current && current.opened && sendOutReports(current), 4);
}

async function main() {
  await init();
  const filters = [{ vendorId: game.usb_vendor_id(), productId: game.usb_product_id() }];
  let hid = navigator.hid;
  if (params.get("hid") === "fake") {
    const device = new FakeHidDevice(filters[0].vendorId, filters[0].productId);
    hid = new FakeHid(device);
    window.fakeHid = { hid, device, input: (b) => device.input(b), sent: device.sent };
  }
  window.spaceFoosball = {
    status: () => JSON.parse(game.status() || "{}"),
    decode: (bytes) => JSON.parse(game.decode_in_report(new Uint8Array(bytes))),
    // The reference match as JSON text (its bits stay exact as text).
    referenceMatch: () => game.reference_match(),
    // Rollbacks of eight frames timed in this page (the desktop's `bench rollback`).
    benchRollback: (repeats) => JSON.parse(game.bench_rollback(repeats)),
    connect: async () => {
      const [device] = await hid.requestDevice({ filters });
      if (device) await attach(device);
    },
  };
  const button = document.getElementById("connect");
  if (!hid) {
    button.disabled = true;
    button.title = "This browser has no WebHID (Chrome or Edge have)";
    return;
  }
  button.addEventListener("click", () => window.spaceFoosball.connect()
    .catch((e) => { message.textContent = `space-foosball: ${e}`; }));
  hid.addEventListener("disconnect", (e) => {
    if (e.device === current) {
      lost = true;
      game.hid_closed();
      boardLabel.textContent = "Board lost: plug it back in";
    }
  });
  // The board plugged back in (WebHID may hand over a new device object) resumes play.
  const isBoard = (d) => d.vendorId === filters[0].vendorId && d.productId === filters[0].productId;
  hid.addEventListener("connect", (e) => {
    if (lost && isBoard(e.device)) attach(e.device).catch((err) => console.warn(err));
  });
  // A board this page was allowed before opens without asking again.
  const known = (await hid.getDevices()).filter(isBoard);
  if (known.length > 0) await attach(known[0]);
}

main().catch((e) => { message.textContent = `space-foosball: ${e}`; console.error(e); });
