// A stand-in for the RP2040 boot ROM and the flash chip's command interface, as far
// as the firmware uses them: the ROM's table lookup (`rom_table_lookup`, the
// pointers at 0x14/0x16/0x18), the flash functions (connect, exit XIP, erase,
// program, flush, enter XIP), `memcpy44`, and `reset_to_usb_boot`; and the W25Q
// flash's "read unique id" command (0x4B) on the SSI.
//
// rp2040js ships no boot ROM and its SSI answers nothing, so without this the
// firmware's flash driver would jump to address 0. The lookup is real Thumb code
// (below); each ROM function that must do something is a `bkpt #n` whose handler
// here does it on the emulator's flash array (erase = 0xFF, program = AND, as NOR
// flash does), then `bx lr`. `reset_to_usb_boot` records its arguments and spins in
// ROM (`b .`), where the real ROM would start its USB mass-storage boot.
//
// Timing: erase and program hold the CPU for the W25Q16JV's typical times (sector
// erase 45 ms, page program 0.4 ms per 256 bytes, datasheet §9.6), since the real
// chip keeps the core (executing from RAM, interrupts off) that long.

const ROM_BYTES = 16 * 1024;
const FUNC_TABLE = 0x100;
const DATA_TABLE = 0x180;
const LOOKUP = 0x40;
const STUBS = 0x60;

/** Sector erase, W25Q16JV typical, microseconds. */
export const ERASE_US_PER_SECTOR = 45_000;
/** Page program, W25Q16JV typical, microseconds per 256 bytes. */
export const PROGRAM_US_PER_PAGE = 400;

const BKPT = { erase: 1, program: 2, memcpy44: 3, usbBoot: 4 };

/** Thumb: rom_table_lookup(table r0, code r1) -> pointer or 0. */
const LOOKUP_CODE = [
  0x8802, // ldrh r2, [r0, #0]
  0x2a00, // cmp r2, #0
  0xd006, // beq not_found (0x54)
  0x428a, // cmp r2, r1
  0xd002, // beq found (0x50)
  0x3004, // adds r0, #4
  0xe7f8, // b loop (0x40)
  0x46c0, // nop
  0x8840, // found: ldrh r0, [r0, #2]
  0x4770, // bx lr
  0x2000, // not_found: movs r0, #0
  0x4770, // bx lr
];

const BX_LR = 0x4770;
const SPIN = 0xe7fe; // b .

/** The ROM functions: code, then the Thumb half-words of its body. */
const FUNCTIONS = [
  ['IF', [BX_LR]], // connect_internal_flash
  ['EX', [BX_LR]], // flash_exit_xip
  ['FC', [BX_LR]], // flash_flush_cache
  ['CX', [BX_LR]], // flash_enter_cmd_xip
  ['RE', [0xbe00 | BKPT.erase, BX_LR]], // flash_range_erase(addr, count, block, cmd)
  ['RP', [0xbe00 | BKPT.program, BX_LR]], // flash_range_program(addr, data, count)
  ['C4', [0xbe00 | BKPT.memcpy44, BX_LR]], // memcpy44(dest, src, n)
  ['UB', [0xbe00 | BKPT.usbBoot, SPIN]], // reset_to_usb_boot(gpio mask, disable mask)
];

/** Whether `address` lies in the boot ROM. */
export function inRom(address) {
  return address >>> 0 < ROM_BYTES;
}

/**
 * Installs the ROM and the flash chip model on `board` (a `Board`).
 * `uniqueId`: the 8 bytes the flash answers to 0x4B.
 * Returns `{ usbBoot, flashOps, eraseUsPerSector }`: `usbBoot` is null until
 * `reset_to_usb_boot` is entered, then `{ gpioMask, disableMask, timeUs }`; `flashOps`
 * lists erases and programs (`{ op, offset, length, timeUs }`); `eraseUsPerSector` is
 * how long an erase holds the CPU per sector (the typical time; a test may set the
 * datasheet's worst, 400 ms).
 */
export function installBootRom(board, { uniqueId }) {
  const rp = board.rp;
  const rom = new Uint8Array(ROM_BYTES);
  const view = new DataView(rom.buffer);
  view.setUint32(0, 0x20042000, true); // initial SP (unused: the harness boots boot2)
  view.setUint32(4, (STUBS + 0x40) | 1, true); // reset (unused)
  rom.set([0x4d, 0x75, 0x01, 0x02], 0x10); // 'M' 'u' 1, version 2
  view.setUint16(0x14, FUNC_TABLE, true);
  view.setUint16(0x16, DATA_TABLE, true);
  view.setUint16(0x18, LOOKUP | 1, true);
  LOOKUP_CODE.forEach((h, i) => view.setUint16(LOOKUP + 2 * i, h, true));
  let at = STUBS;
  let entry = FUNC_TABLE;
  for (const [code, body] of FUNCTIONS) {
    view.setUint16(entry, code.charCodeAt(0) | (code.charCodeAt(1) << 8), true);
    view.setUint16(entry + 2, at | 1, true);
    entry += 4;
    body.forEach((h, i) => view.setUint16(at + 2 * i, h, true));
    at += 4;
  }
  view.setUint16(entry, 0, true); // end of the function table
  view.setUint16(DATA_TABLE, 0, true); // empty data table
  // Not `loadBootrom`: it also resets the chip and erases the flash image.
  rp.bootrom.set(new Uint32Array(rom.buffer));

  const state = { usbBoot: null, flashOps: [], eraseUsPerSector: ERASE_US_PER_SECTOR };
  const reg = (n) => rp.core.registers[n] >>> 0;
  const flash = rp.flash;
  const checkRange = (offset, length, what) => {
    if (offset + length > flash.length) {
      throw new Error(`${what} past the end of flash: 0x${offset.toString(16)} + ${length}`);
    }
  };
  rp.onBreak = (code) => {
    switch (code) {
      case BKPT.erase: {
        const [offset, length] = [reg(0), reg(1)];
        if (offset % 4096 || length % 4096) {
          throw new Error(`flash_range_erase not sector-aligned: 0x${offset.toString(16)} + ${length}`);
        }
        checkRange(offset, length, 'erase');
        flash.fill(0xff, offset, offset + length);
        state.flashOps.push({ op: 'erase', offset, length, timeUs: board.timeUs });
        board.holdCpu((length / 4096) * state.eraseUsPerSector);
        return;
      }
      case BKPT.program: {
        const [offset, data, length] = [reg(0), reg(1), reg(2)];
        if (offset % 256 || length % 256) {
          throw new Error(`flash_range_program not page-aligned: 0x${offset.toString(16)} + ${length}`);
        }
        checkRange(offset, length, 'program');
        for (let i = 0; i < length; i++) {
          flash[offset + i] &= rp.readUint8(data + i);
        }
        state.flashOps.push({ op: 'program', offset, length, timeUs: board.timeUs });
        board.holdCpu((length / 256) * PROGRAM_US_PER_PAGE);
        return;
      }
      case BKPT.memcpy44: {
        const [dest, src, length] = [reg(0), reg(1), reg(2)];
        for (let i = 0; i < length; i++) {
          rp.writeUint8(dest + i, rp.readUint8(src + i));
        }
        return;
      }
      case BKPT.usbBoot:
        if (!state.usbBoot) {
          state.usbBoot = { gpioMask: reg(0), disableMask: reg(1), timeUs: board.timeUs };
        }
        return;
      default:
        throw new Error(`breakpoint #${code} at 0x${(rp.core.PC >>> 0).toString(16)}`);
    }
  };

  // The flash chip on the SSI: after the command byte 0x4B, four dummy bytes,
  // then the 8-byte unique id. Every other command reads zeros as before.
  const ssi = rp.peripherals[0x18000];
  const DR0 = 0x60;
  const readUint32 = ssi.readUint32.bind(ssi);
  const writeUint32 = ssi.writeUint32.bind(ssi);
  let replies = [];
  ssi.writeUint32 = (offset, value) => {
    if (offset === DR0) {
      replies = (value & 0xff) === 0x4b ? [0, 0, 0, 0, ...uniqueId] : [];
    }
    writeUint32(offset, value);
  };
  ssi.readUint32 = (offset) => {
    if (offset === DR0 && replies.length) {
      return replies.shift();
    }
    return readUint32(offset);
  };
  // XIP_CTRL (0x14000000, datasheet §2.6.3.1), which rp2040js does not map: the
  // flash driver waits for STREAM_CTR to be 0 and for no other register here.
  // Every register reads 0 (no streaming transfer, cache idle); writes do nothing.
  const XIP_CTRL = 0x14000000;
  const inXipCtrl = (address) => address >>> 0 >= XIP_CTRL && address >>> 0 < XIP_CTRL + 0x40;
  const read32 = rp.readUint32.bind(rp);
  const write32 = rp.writeUint32.bind(rp);
  rp.readUint32 = (address) => (inXipCtrl(address) ? 0 : read32(address));
  rp.writeUint32 = (address, value) => {
    if (!inXipCtrl(address)) {
      write32(address, value);
    }
  };
  return state;
}
