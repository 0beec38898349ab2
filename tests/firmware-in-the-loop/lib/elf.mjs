// A minimal ELF32 little-endian reader: program headers (what to load where),
// section headers and the symbol table (RTT control block, defmt strings).

const PT_LOAD = 1;
const SHT_SYMTAB = 2;

export class Elf {
  /** @param {Uint8Array} bytes the whole ELF file */
  constructor(bytes) {
    this.bytes = bytes;
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.view = view;
    if (view.getUint32(0, false) !== 0x7f454c46) {
      throw new Error('not an ELF file');
    }
    if (bytes[4] !== 1 || bytes[5] !== 1) {
      throw new Error('expected a 32-bit little-endian ELF');
    }
    this.entry = view.getUint32(24, true);
    const phoff = view.getUint32(28, true);
    const shoff = view.getUint32(32, true);
    const phentsize = view.getUint16(42, true);
    const phnum = view.getUint16(44, true);
    const shentsize = view.getUint16(46, true);
    const shnum = view.getUint16(48, true);
    const shstrndx = view.getUint16(50, true);

    this.programHeaders = [];
    for (let i = 0; i < phnum; i++) {
      const at = phoff + i * phentsize;
      this.programHeaders.push({
        type: view.getUint32(at, true),
        offset: view.getUint32(at + 4, true),
        vaddr: view.getUint32(at + 8, true),
        paddr: view.getUint32(at + 12, true),
        filesz: view.getUint32(at + 16, true),
        memsz: view.getUint32(at + 20, true),
      });
    }

    this.sections = [];
    for (let i = 0; i < shnum; i++) {
      const at = shoff + i * shentsize;
      this.sections.push({
        nameOffset: view.getUint32(at, true),
        type: view.getUint32(at + 4, true),
        addr: view.getUint32(at + 12, true),
        offset: view.getUint32(at + 16, true),
        size: view.getUint32(at + 20, true),
        link: view.getUint32(at + 24, true),
        entsize: view.getUint32(at + 36, true),
      });
    }
    const names = this.sections[shstrndx];
    for (const section of this.sections) {
      section.name = names ? this.cString(names.offset + section.nameOffset) : '';
    }
    this.symbols = this.readSymbols();
  }

  cString(offset) {
    let end = offset;
    while (end < this.bytes.length && this.bytes[end] !== 0) {
      end++;
    }
    return new TextDecoder().decode(this.bytes.subarray(offset, end));
  }

  readSymbols() {
    const symbols = [];
    const symtab = this.sections.find((s) => s.type === SHT_SYMTAB);
    if (!symtab) {
      return symbols;
    }
    const strtab = this.sections[symtab.link];
    for (let at = symtab.offset; at + 16 <= symtab.offset + symtab.size; at += 16) {
      const name = this.cString(strtab.offset + this.view.getUint32(at, true));
      const shndx = this.view.getUint16(at + 14, true);
      symbols.push({
        name,
        value: this.view.getUint32(at + 4, true),
        size: this.view.getUint32(at + 8, true),
        section: this.sections[shndx]?.name ?? '',
      });
    }
    return symbols;
  }

  symbol(name) {
    return this.symbols.find((s) => s.name === name);
  }

  /** The file contents of every PT_LOAD segment, at its physical (load) address. */
  loadSegments() {
    return this.programHeaders
      .filter((ph) => ph.type === PT_LOAD && ph.filesz > 0)
      .map((ph) => ({
        address: ph.paddr,
        data: this.bytes.subarray(ph.offset, ph.offset + ph.filesz),
      }));
  }
}
