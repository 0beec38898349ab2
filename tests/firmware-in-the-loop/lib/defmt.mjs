// A small defmt decoder (wire format version 4, rzCOBS encoding): enough for the
// firmware's log messages and the types they format (integers, slices, strings,
// derived structs and enums, Option, Display/Debug adapters, format sequences).
//
// The interned strings come from the ELF: every symbol of the `.defmt` section is
// named by a JSON object ({"package", "tag", "data", ...}); the symbol's value is
// the string's index on the wire.

const LEVEL_TAGS = {
  defmt_trace: 'TRACE',
  defmt_debug: 'DEBUG',
  defmt_info: 'INFO',
  defmt_warn: 'WARN',
  defmt_error: 'ERROR',
  defmt_println: 'PRINT',
};

/** The interned strings of an ELF: index → { tag, data, level }. */
export function defmtTable(elf) {
  const table = new Map();
  let timestamp = null;
  let encoding = null;
  for (const symbol of elf.symbols) {
    if (symbol.name === '_defmt_encoding_ = rzcobs') {
      encoding = 'rzcobs';
    } else if (symbol.name === '_defmt_encoding_ = raw') {
      encoding = 'raw';
    }
    if (symbol.section !== '.defmt' || !symbol.name.startsWith('{')) {
      continue;
    }
    let entry;
    try {
      entry = JSON.parse(symbol.name);
    } catch {
      continue;
    }
    const item = { tag: entry.tag, data: entry.data, level: LEVEL_TAGS[entry.tag] ?? null };
    table.set(symbol.value & 0xffff, item);
    if (entry.tag === 'defmt_timestamp') {
      timestamp = item.data;
    }
  }
  return { table, timestamp, encoding: encoding ?? 'rzcobs' };
}

/** Undoes rzCOBS on one frame (without its 0x00 terminator). */
export function rzcobsDecode(bytes) {
  const out = [];
  let i = bytes.length - 1;
  const next = () => {
    if (i < 0) {
      throw new Error('malformed rzCOBS frame');
    }
    return bytes[i--];
  };
  while (i >= 0) {
    const x = next();
    if (x === 0) {
      throw new Error('malformed rzCOBS frame');
    } else if (x < 0x80) {
      for (let bit = 0; bit < 7; bit++) {
        out.push(x & (1 << (6 - bit)) ? 0 : next());
      }
    } else if (x < 0xff) {
      out.push(0);
      for (let n = (x & 0x7f) + 7; n > 0; n--) {
        out.push(next());
      }
    } else {
      for (let n = 0; n < 134; n++) {
        out.push(next());
      }
    }
  }
  return Uint8Array.from(out.reverse());
}

/** Reads little-endian values; reading past the end yields zeros (rzCOBS drops trailing zeros). */
class Reader {
  constructor(bytes) {
    this.bytes = bytes;
    this.at = 0;
  }
  u8() {
    return this.at < this.bytes.length ? this.bytes[this.at++] : (this.at++, 0);
  }
  uint(size) {
    let value = 0n;
    for (let i = 0; i < size; i++) {
      value |= BigInt(this.u8()) << BigInt(8 * i);
    }
    return value;
  }
  int(size) {
    return BigInt.asIntN(size * 8, this.uint(size));
  }
  take(n) {
    const out = [];
    for (let i = 0; i < n; i++) {
      out.push(this.u8());
    }
    return out;
  }
}

/** Splits a format string into literal text and `{...}` parameters. */
function parseFormat(format) {
  const pieces = [];
  let text = '';
  let implicit = 0;
  for (let i = 0; i < format.length; i++) {
    const c = format[i];
    if (c === '{' && format[i + 1] === '{') {
      text += '{';
      i++;
    } else if (c === '}' && format[i + 1] === '}') {
      text += '}';
      i++;
    } else if (c === '{') {
      const end = format.indexOf('}', i);
      const spec = format.slice(i + 1, end);
      i = end;
      if (text) {
        pieces.push({ text });
        text = '';
      }
      const match = /^(\d*)(?:=([^:]*))?(?::(.*))?$/.exec(spec) ?? [];
      const index = match[1] ? Number(match[1]) : implicit++;
      pieces.push({ param: { index, type: match[2] ?? '?', hint: match[3] ?? '' } });
    } else {
      text += c;
    }
  }
  if (text) {
    pieces.push({ text });
  }
  return pieces;
}

/** Splits an enum's format string ("A|B(..)|C { .. }") at top-level bars. */
function splitVariants(format) {
  const variants = [];
  let depth = 0;
  let start = 0;
  for (let i = 0; i < format.length; i++) {
    const c = format[i];
    if ((c === '{' || c === '}') && format[i + 1] === c) {
      i++;
    } else if (c === '{') {
      depth++;
    } else if (c === '}') {
      depth--;
    } else if (c === '|' && depth === 0) {
      variants.push(format.slice(start, i));
      start = i + 1;
    }
  }
  variants.push(format.slice(start));
  return variants;
}

const INTEGER_SIZES = { u8: 1, u16: 2, u32: 4, u64: 8, u128: 16, usize: 4, i8: 1, i16: 2, i32: 4, i64: 8, i128: 16, isize: 4 };

function formatInteger(value, hint) {
  const m = /^(#)?(0)?(\d+)?([xXbo])?$/.exec(hint.replace(/\?$/, '')) ?? [];
  const [, alternate, zero, width, radixChar] = m;
  if (!radixChar) {
    return value.toString();
  }
  const radix = { x: 16, X: 16, b: 2, o: 8 }[radixChar];
  let digits = (value < 0n ? -value : value).toString(radix);
  if (radixChar === 'X') {
    digits = digits.toUpperCase();
  }
  const prefix = alternate ? { x: '0x', X: '0x', b: '0b', o: '0o' }[radixChar] : '';
  const w = width ? Number(width) - prefix.length - (value < 0n ? 1 : 0) : 0;
  if (zero && digits.length < w) {
    digits = '0'.repeat(w - digits.length) + digits;
  }
  return (value < 0n ? '-' : '') + prefix + digits;
}

export class DefmtDecoder {
  constructor({ table, timestamp, encoding }) {
    this.table = table;
    this.timestamp = timestamp;
    this.encoding = encoding;
    this.pending = [];
  }

  /** Feeds raw RTT bytes; returns the decoded messages [{ level, text }]. */
  feed(bytes) {
    const messages = [];
    for (const byte of bytes) {
      if (byte !== 0) {
        this.pending.push(byte);
        continue;
      }
      const frame = this.pending;
      this.pending = [];
      if (frame.length === 0) {
        continue;
      }
      try {
        messages.push(this.decodeFrame(rzcobsDecode(Uint8Array.from(frame))));
      } catch (err) {
        messages.push({ level: 'ERROR', text: `<defmt decode error: ${err.message}>` });
      }
    }
    return messages;
  }

  decodeFrame(bytes) {
    const reader = new Reader(bytes);
    const index = Number(reader.uint(2));
    const entry = this.table.get(index);
    if (!entry) {
      throw new Error(`unknown string index ${index}`);
    }
    let stamp = '';
    if (this.timestamp) {
      stamp = this.render(this.timestamp, reader) + ' ';
    }
    return { level: entry.level ?? 'PRINT', text: stamp + this.render(entry.data, reader) };
  }

  /** Decodes a format string's arguments from `reader` and renders it. */
  render(format, reader) {
    const pieces = parseFormat(format);
    const params = new Map();
    for (const piece of pieces) {
      if (piece.param && !params.has(piece.param.index)) {
        params.set(piece.param.index, piece.param);
      }
    }
    const values = new Map();
    for (const index of [...params.keys()].sort((a, b) => a - b)) {
      values.set(index, this.readArg(params.get(index), reader));
    }
    return pieces
      .map((piece) => {
        if (piece.text !== undefined) {
          return piece.text;
        }
        const { type, hint } = piece.param;
        return this.show(values.get(piece.param.index), type, hint);
      })
      .join('');
  }

  /** A nested `Format` value: its string index, then its data. */
  readNested(reader) {
    const index = Number(reader.uint(2));
    return this.readTagged(index, reader);
  }

  readTagged(index, reader) {
    const entry = this.table.get(index);
    if (!entry) {
      throw new Error(`unknown string index ${index}`);
    }
    const variants = splitVariants(entry.data);
    if (variants.length === 1) {
      return { rendered: this.render(entry.data, reader) };
    }
    const size = variants.length <= 255 ? 1 : variants.length <= 65535 ? 2 : 4;
    const discriminant = Number(reader.uint(size));
    const variant = variants[discriminant];
    if (variant === undefined) {
      throw new Error(`bad discriminant ${discriminant} for "${entry.data}"`);
    }
    return { rendered: this.render(variant, reader) };
  }

  readArg({ type }, reader) {
    if (type in INTEGER_SIZES) {
      const size = INTEGER_SIZES[type];
      return type.startsWith('i') ? reader.int(size) : reader.uint(size);
    }
    switch (type) {
      case 'bool':
        return reader.u8() !== 0;
      case 'f32': {
        const view = new DataView(new ArrayBuffer(4));
        view.setUint32(0, Number(reader.uint(4)), true);
        return view.getFloat32(0, true);
      }
      case 'f64': {
        const view = new DataView(new ArrayBuffer(8));
        view.setBigUint64(0, reader.uint(8), true);
        return view.getFloat64(0, true);
      }
      case 'char':
        return String.fromCodePoint(Number(reader.uint(4)));
      case 'str':
        return new TextDecoder().decode(Uint8Array.from(reader.take(Number(reader.uint(4)))));
      case 'istr': {
        const entry = this.table.get(Number(reader.uint(2)));
        return entry ? entry.data : '<?>';
      }
      case '[u8]':
        return reader.take(Number(reader.uint(4)));
      case '?':
        return this.readNested(reader);
      case '[?]': {
        const length = Number(reader.uint(4));
        const index = Number(reader.uint(2));
        return Array.from({ length }, () => this.readTagged(index, reader));
      }
      case '__internal_Display':
      case '__internal_Debug': {
        const bytes = [];
        for (let b = reader.u8(); b !== 0xff && reader.at <= reader.bytes.length; b = reader.u8()) {
          bytes.push(b);
        }
        return new TextDecoder().decode(Uint8Array.from(bytes));
      }
      case '__internal_FormatSequence': {
        const parts = [];
        for (;;) {
          const index = Number(reader.uint(2));
          if (index === 0 || reader.at > reader.bytes.length) {
            break;
          }
          parts.push(this.readTagged(index, reader).rendered);
        }
        return { rendered: parts.join('') };
      }
    }
    let m = /^\[u8; *(\d+)\]$/.exec(type);
    if (m) {
      return reader.take(Number(m[1]));
    }
    m = /^\[\?; *(\d+)\]$/.exec(type);
    if (m) {
      const index = Number(reader.uint(2));
      return Array.from({ length: Number(m[1]) }, () => this.readTagged(index, reader));
    }
    throw new Error(`unsupported defmt type {=${type}}`);
  }

  show(value, type, hint) {
    if (typeof value === 'bigint') {
      return formatInteger(value, hint);
    }
    if (Array.isArray(value)) {
      const items = value.map((v) =>
        typeof v === 'number' ? formatInteger(BigInt(v), hint) : (v.rendered ?? String(v)),
      );
      return `[${items.join(', ')}]`;
    }
    if (value && typeof value === 'object' && 'rendered' in value) {
      return value.rendered;
    }
    if (type === 'str' && hint.startsWith('?')) {
      return JSON.stringify(value);
    }
    return String(value);
  }
}
