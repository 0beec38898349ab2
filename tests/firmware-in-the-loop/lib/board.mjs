// The emulated sensor board: rp2040js running the firmware ELF, with
//  * an ELF loader (PT_LOAD segments into flash) and a boot through boot2,
//  * the PIO state machines stepped on the emulated clock (the patched
//    `StateMachine.tick`, once per state machine clock: clk_sys / CLKDIV),
//  * open-drain wires with pull-ups for the PS/2 lines (the board or a device
//    pulls a line low, nobody pulling = high),
//  * the defmt log pulled from the RTT up-buffer in RAM and decoded,
//  * edge recording on output pins (PWM pulses).
import { readFileSync } from 'node:fs';
import { RP2040, ConsoleLogger, LogLevel } from 'rp2040js';
import { Elf } from './elf.mjs';
import { DefmtDecoder, defmtTable } from './defmt.mjs';
import { readUf2 } from './uf2.mjs';
import { installBootRom } from './boot-rom.mjs';

export const FLASH_BASE = 0x10000000;
const RAM_BASE = 0x20000000;
const RAM_TOP = 0x20042000;
/** How often the RTT buffer is drained, emulated nanoseconds. */
const RTT_POLL_NS = 100_000;
/** The RP2040 PIO runs a state machine at most once per clk_sys cycle; this is
 *  the longest gap between two looks at whether a machine got enabled. */
const PIO_IDLE_CHECK_NS = 1000;

/** The flash unique id the emulated board has unless told otherwise. */
export const DEFAULT_UNIQUE_ID = [0xe6, 0x60, 0x58, 0x38, 0x83, 0x4b, 0x21, 0x2f];

export class Board {
  /**
   * @param {string} elfPath the firmware ELF
   * @param {{ onLog?: (msg: {level: string, text: string, timeUs: number}) => void,
   *           uf2Path?: string, uniqueId?: number[], flashImage?: Uint8Array,
   *           sramImage?: Uint8Array }} options
   *   uf2Path: flash comes from this UF2 (checked block by block, `readUf2`), as the
   *   bootrom would write it; the ELF then only gives the symbols (RTT, defmt)
   *   uniqueId: the flash chip's 8-byte unique id (the USB serial number)
   *   flashImage: the whole flash as another board left it (a power cycle: what the
   *   firmware wrote survives); replaces the UF2's and the ELF's image
   *   sramImage: the RAM as another board left it (a reset through the RUN pin: SRAM
   *   keeps its contents, the chip starts again from the boot ROM)
   */
  constructor(elfPath, { onLog, uf2Path, uniqueId = DEFAULT_UNIQUE_ID, flashImage, sramImage } = {}) {
    this.elf = new Elf(new Uint8Array(readFileSync(elfPath)));
    const rp = new RP2040();
    this.rp = rp;
    this.clock = rp.clock;
    this.emulatorWarnings = [];
    const logger = new ConsoleLogger(LogLevel.Warn, false);
    logger.warn = (component, message) => {
      if (this.emulatorWarnings.length < 100) {
        this.emulatorWarnings.push(`[${component}] ${message}`);
      }
    };
    logger.error = (component, message) => {
      throw new Error(`rp2040js [${component}] ${message}`);
    };
    rp.logger = logger;

    if (uf2Path) {
      // Flash as the bootrom writes it from the UF2; RAM starts empty (the reset
      // handler copies .data from flash).
      const { start, image } = readUf2(new Uint8Array(readFileSync(uf2Path)), {
        flashBase: FLASH_BASE,
        flashBytes: rp.flash.length,
      });
      rp.flash.set(image, start - FLASH_BASE);
      this.bootedFrom = uf2Path;
    }
    // Flash: every loadable segment at its load address (unless from a UF2).
    for (const { address, data } of uf2Path ? [] : this.elf.loadSegments()) {
      if (address >= FLASH_BASE && address + data.length <= FLASH_BASE + rp.flash.length) {
        rp.flash.set(data, address - FLASH_BASE);
      } else if (address >= RAM_BASE && address + data.length <= RAM_TOP) {
        rp.sram.set(data, address - RAM_BASE);
      } else {
        throw new Error(`ELF segment at 0x${address.toString(16)} is outside flash and RAM`);
      }
    }

    if (flashImage) {
      rp.flash.set(flashImage);
    }
    if (sramImage) {
      rp.sram.set(sramImage);
    }
    // The ROM functions and the flash chip's unique id (`boot-rom.mjs`).
    this.rom = installBootRom(this, { uniqueId });

    // Boot as the bootrom would hand over to boot2: boot2 runs from the start of
    // flash with the stack at the top of RAM and LR = 0 ("vector into flash":
    // boot2 sets VTOR = 0x10000100, loads SP and jumps to the reset handler).
    rp.core.SP = RAM_TOP;
    rp.core.LR = 0;
    rp.core.PC = FLASH_BASE;

    // The watchdog: count resets; the tests require none.
    this.watchdogResets = 0;
    rp.peripherals[0x40058].onWatchdogTrigger = () => {
      this.watchdogResets++;
    };

    // defmt over RTT.
    const decoderTable = defmtTable(this.elf);
    this.defmt = new DefmtDecoder(decoderTable);
    this.rttAddress = this.elf.symbol('_SEGGER_RTT')?.value ?? null;
    this.log = [];
    this.onLog = onLog;
    this.rttAlarm = this.clock.createAlarm(() => {
      this.drainRtt();
      this.rttAlarm.schedule(RTT_POLL_NS);
    });
    this.rttAlarm.schedule(RTT_POLL_NS);

    // PIO stepping state, per state machine: next tick time and cycle count.
    this.machines = rp.pio.flatMap((pio) => pio.machines);
    for (const sm of this.machines) {
      sm.fitlNextNanos = null;
      sm.fitlCount = 0;
    }
    this.nextPioNanos = 0;
    this.cpuHeldUntilNs = 0;

    // Wires with pull-ups, keyed by GPIO.
    this.wires = new Map();
    this.edgeRecorders = new Map();
  }

  get timeNs() {
    return this.clock.nanosCounter;
  }

  get timeUs() {
    return this.clock.nanosCounter / 1000;
  }

  /** Nanoseconds per clk_sys cycle (follows the firmware's clock setup). */
  get cycleNanos() {
    return 1e9 / this.rp.clkSys;
  }

  // ---- wires -------------------------------------------------------------

  /**
   * Makes `pin` an open-drain wire with a pull-up: high unless the board drives
   * it low (output enabled, level low) or a device pulls it low.
   * `onChange(level)` is called whenever the wire's level changes.
   */
  attachWire(pin, onChange) {
    const wire = { deviceLow: false, level: true, listeners: [] };
    if (onChange) {
      wire.listeners.push(onChange);
    }
    this.wires.set(pin, wire);
    this.rp.gpio[pin].addListener(() => this.updateWire(pin));
    this.rp.gpio[pin].setInputValue(true);
    return wire;
  }

  /** Whether the board itself pulls `pin` low. */
  boardPullsLow(pin) {
    const gpio = this.rp.gpio[pin];
    return gpio.outputEnable && !gpio.outputValue;
  }

  /** A device pulls the wire low (`true`) or releases it (`false`). */
  setDeviceLow(pin, low) {
    const wire = this.wires.get(pin);
    wire.deviceLow = low;
    this.updateWire(pin);
  }

  wireLevel(pin) {
    return this.wires.get(pin).level;
  }

  updateWire(pin) {
    const wire = this.wires.get(pin);
    if (!wire) {
      return;
    }
    const level = !(wire.deviceLow || this.boardPullsLow(pin));
    if (level !== wire.level) {
      wire.level = level;
      this.rp.gpio[pin].setInputValue(level);
      for (const listener of wire.listeners) {
        listener(level);
      }
    }
  }

  // ---- output edges (PWM) ------------------------------------------------

  /** Records the output level changes of `pin` as [{ timeNs, high }]. */
  recordEdges(pin) {
    const edges = [];
    const gpio = this.rp.gpio[pin];
    let last = gpio.outputEnable && gpio.outputValue;
    gpio.addListener(() => {
      const high = gpio.outputEnable && gpio.outputValue;
      if (high !== last) {
        last = high;
        edges.push({ timeNs: this.timeNs, high });
      }
    });
    this.edgeRecorders.set(pin, edges);
    return edges;
  }

  // ---- RTT / defmt -------------------------------------------------------

  drainRtt() {
    if (this.rttAddress === null) {
      return;
    }
    const rp = this.rp;
    const cb = this.rttAddress;
    // Control block: id[16], max_up, max_down, then up buffer 0:
    // name, buffer, size, write, read, flags.
    if (rp.readUint32(cb + 16) < 1) {
      return;
    }
    const up = cb + 24;
    const buffer = rp.readUint32(up + 4);
    const size = rp.readUint32(up + 8);
    const write = rp.readUint32(up + 12);
    let read = rp.readUint32(up + 16);
    if (!buffer || !size || write === read || write >= size) {
      return;
    }
    const bytes = [];
    while (read !== write) {
      bytes.push(rp.sram[buffer - RAM_BASE + read]);
      read = (read + 1) % size;
    }
    rp.writeUint32(up + 16, read);
    for (const message of this.defmt.feed(bytes)) {
      const entry = { ...message, timeUs: this.timeUs };
      this.log.push(entry);
      this.onLog?.(entry);
    }
  }

  /** Log messages whose text matches `pattern`, from index `since`. */
  logMatching(pattern, since = 0) {
    return this.log.slice(since).filter((m) => pattern.test(m.text));
  }

  // ---- running -----------------------------------------------------------

  /** One look at the PIO blocks: tick every enabled state machine that is due. */
  pioTick() {
    const now = this.clock.nanosCounter;
    let next = now + PIO_IDLE_CHECK_NS;
    for (const sm of this.machines) {
      if (!sm.enabled) {
        sm.fitlNextNanos = null;
        continue;
      }
      const period = sm.clockDivider * this.cycleNanos;
      if (sm.fitlNextNanos === null) {
        // Newly enabled: its clock runs on the grid of its period from time 0, so
        // machines with the same divider tick together (one look per cycle).
        sm.fitlNextNanos = Math.ceil(now / period - 1e-9) * period;
      }
      if (sm.fitlNextNanos <= now) {
        sm.tick(sm.fitlCount++);
        sm.fitlNextNanos += period;
      }
      if (sm.fitlNextNanos < next) {
        next = sm.fitlNextNanos;
      }
    }
    for (const pio of this.rp.pio) {
      pio.checkChangedPins();
    }
    this.nextPioNanos = next;
  }

  /** Runs the CPU, the peripherals and the PIO until emulated time `targetNs`. */
  runUntilNs(targetNs) {
    const { core } = this.rp;
    const clock = this.clock;
    while (clock.nanosCounter < targetNs) {
      const pioDue = this.nextPioNanos <= targetNs;
      const stopAt = pioDue ? this.nextPioNanos : targetNs;
      const cycleNanos = this.cycleNanos;
      while (clock.nanosCounter < stopAt) {
        if (core.waiting || clock.nanosCounter < this.cpuHeldUntilNs) {
          const alarm = clock.nextAlarm;
          let until = alarm && alarm.nanos < stopAt ? alarm.nanos : stopAt;
          if (!core.waiting) {
            until = Math.min(until, this.cpuHeldUntilNs);
          }
          clock.tick(Math.max(0, until - clock.nanosCounter));
        } else {
          clock.tick(core.executeInstruction() * cycleNanos);
        }
      }
      if (pioDue) {
        this.pioTick();
      }
    }
  }

  /**
   * Holds the CPU for `us` microseconds from now (a fault: as if a long interrupt
   * or a flash operation kept the core busy): no instruction runs, while the
   * clock, the timers, the PIO, the mice and the host go on.
   */
  holdCpu(us) {
    this.cpuHeldUntilNs = this.clock.nanosCounter + us * 1000;
  }

  /** Runs for `us` microseconds of emulated time. */
  runUs(us) {
    this.runUntilNs(this.clock.nanosCounter + us * 1000);
  }

  /**
   * Runs until `predicate()` is true (checked every `stepUs`), at most `timeoutUs`;
   * returns whether it became true.
   */
  runUntil(predicate, timeoutUs, stepUs = 100) {
    const end = this.clock.nanosCounter + timeoutUs * 1000;
    while (!predicate()) {
      if (this.clock.nanosCounter >= end) {
        return false;
      }
      this.runUntilNs(Math.min(end, this.clock.nanosCounter + stepUs * 1000));
    }
    return true;
  }
}
