//! The mutator: turns a pool input into a new one.
//!
//! No coverage feedback: byte edits (bit flips, edge-value bytes and `i16`s, inserts,
//! deletes, duplicated runs, splices with another pool input) for every format, and
//! for JSON and TOML also edits of the parsed value tree, which keep the text parseable
//! so that it reaches the validation and the physics: a number set to an edge value
//! (0, −0, ±1, subnormals, 1e19, 1e30, 1e300, the integer limits; TOML also NaN and
//! ±inf) or scaled by a power of ten, an array element duplicated, removed or the array
//! emptied, a key removed, a string emptied or swapped for a known one.

use space_foosball::play::MatchRng;

use crate::Format;

/// Floats tried where a number was.
const EDGE_FLOATS: [f64; 22] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    2.0,
    5e-324,
    1e-308,
    1e-300,
    1e-12,
    1e-6,
    1e6,
    1e7,
    1e9,
    1.6e19,
    1e19,
    1e30,
    1e100,
    1e300,
    -1e300,
    1.7976931348623157e308,
    -1.7976931348623157e308,
];

/// Integers tried where a number was.
const EDGE_INTS: [i64; 10] = [
    0,
    1,
    -1,
    2,
    64,
    65,
    1_000_000,
    i64::MAX,
    i64::MIN,
    10_000_000,
];

/// Bytes tried by byte edits: the protocol's and the PS/2 driver's special values.
const EDGE_BYTES: [u8; 12] = [
    0x00, 0x01, 0x02, 0x03, 0x7F, 0x80, 0xFF, 0xAA, 0xFA, 0xFE, 0xFC, 0x40,
];

/// Strings tried where a string was (known names and formats of the project's files).
const STRINGS: [&str; 10] = [
    "",
    "standard",
    "paper",
    "gravity",
    "contacts",
    "space-foosball-calibration",
    "space-foosball-recording",
    "goalkeeper",
    "box",
    "\u{0}",
];

/// Random choices for the mutator.
pub struct Rng(MatchRng);

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self(MatchRng::new(seed))
    }

    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.0.next_u64() % n.max(1) as u64) as usize
    }

    /// True with probability `1 / n`.
    pub fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }

    /// 64 random bits.
    pub fn bits(&mut self) -> u64 {
        self.0.next_u64()
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// A mutant of `input` (`other` is a second pool input for splices), at most
/// `max_len` bytes.
pub fn mutate(
    format: Format,
    input: &[u8],
    other: &[u8],
    rng: &mut Rng,
    max_len: usize,
) -> Vec<u8> {
    let mut out = match format {
        Format::Json if !rng.one_in(4) => {
            tree_mutant(input, rng, parse_json, |v| serde_json::to_vec(v).ok())
        }
        Format::Toml if !rng.one_in(4) => tree_mutant(input, rng, parse_toml, |v| {
            toml::to_string(v).ok().map(String::into_bytes)
        }),
        _ => None,
    }
    .unwrap_or_else(|| input.to_vec());
    if out == input {
        let edits = 1 + rng.below(4);
        for _ in 0..edits {
            byte_edit(&mut out, other, rng);
        }
    }
    out.truncate(max_len);
    out
}

/// One byte-level edit of `data` in place.
pub fn byte_edit(data: &mut Vec<u8>, other: &[u8], rng: &mut Rng) {
    let len = data.len();
    match rng.below(9) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = *rng.pick(&EDGE_BYTES);
        }
        2 if len > 0 => {
            let i = rng.below(len);
            data[i] = rng.bits() as u8;
        }
        3 => {
            let i = rng.below(len + 1);
            let b = if rng.one_in(2) {
                *rng.pick(&EDGE_BYTES)
            } else {
                rng.bits() as u8
            };
            data.insert(i, b);
        }
        4 if len > 0 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(16));
            data.drain(i..i + n);
        }
        5 if len > 0 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(64));
            let run = data[i..i + n].to_vec();
            let at = rng.below(len + 1);
            data.splice(at..at, run);
        }
        6 if len >= 2 => {
            let i = rng.below(len - 1);
            let v = *rng.pick(&[0i16, 1, -1, i16::MAX, i16::MIN, 255, 256, -256]);
            data[i..i + 2].copy_from_slice(&v.to_le_bytes());
        }
        7 if !other.is_empty() => {
            let cut = rng.below(len + 1);
            let from = rng.below(other.len());
            data.truncate(cut);
            data.extend_from_slice(&other[from..]);
        }
        _ if len > 0 => data.truncate(rng.below(len)),
        _ => data.push(rng.bits() as u8),
    }
}

/// A value tree the mutator edits: JSON's or TOML's.
trait Tree: Sized {
    /// The children, if this is an array or a table/object.
    fn children(&mut self) -> Vec<&mut Self>;
    /// Edits this node; false if nothing fitting could be done.
    fn edit(&mut self, rng: &mut Rng) -> bool;
}

fn parse_json(text: &str) -> Option<serde_json::Value> {
    serde_json::from_str(text).ok()
}

fn parse_toml(text: &str) -> Option<toml::Value> {
    text.parse::<toml::Table>().ok().map(toml::Value::Table)
}

fn tree_mutant<T: Tree>(
    input: &[u8],
    rng: &mut Rng,
    parse: fn(&str) -> Option<T>,
    print: fn(&T) -> Option<Vec<u8>>,
) -> Option<Vec<u8>> {
    let mut tree = parse(std::str::from_utf8(input).ok()?)?;
    let edits = 1 + rng.below(3);
    let mut changed = false;
    for _ in 0..edits {
        changed |= edit_random_node(&mut tree, rng);
    }
    if changed {
        print(&tree)
    } else {
        None
    }
}

/// Walks down from `node` to a random depth and edits the node reached.
fn edit_random_node<T: Tree>(node: &mut T, rng: &mut Rng) -> bool {
    if rng.one_in(4) {
        return node.edit(rng);
    }
    let mut children = node.children();
    if children.is_empty() {
        drop(children);
        return node.edit(rng);
    }
    let i = rng.below(children.len());
    edit_random_node(children.swap_remove(i), rng)
}

fn edge_float(old: f64, rng: &mut Rng) -> f64 {
    if rng.one_in(3) && old.is_finite() {
        let scale = 10f64.powi(rng.below(40) as i32 - 10);
        let sign = if rng.one_in(4) { -1.0 } else { 1.0 };
        sign * old * scale
    } else {
        *rng.pick(&EDGE_FLOATS)
    }
}

impl Tree for serde_json::Value {
    fn children(&mut self) -> Vec<&mut Self> {
        match self {
            Self::Array(items) => items.iter_mut().collect(),
            Self::Object(map) => map.values_mut().collect(),
            _ => Vec::new(),
        }
    }

    fn edit(&mut self, rng: &mut Rng) -> bool {
        use serde_json::Value;
        match self {
            Value::Number(n) => {
                *self = if rng.one_in(3) {
                    Value::from(*rng.pick(&EDGE_INTS))
                } else {
                    let f = edge_float(n.as_f64().unwrap_or(0.0), rng);
                    serde_json::Number::from_f64(f).map_or(Value::Null, Value::Number)
                };
                true
            }
            Value::Array(items) => edit_array(items, rng),
            Value::Object(map) => {
                if map.is_empty() {
                    return false;
                }
                let key = map.keys().nth(rng.below(map.len())).cloned();
                if let Some(key) = key {
                    map.remove(&key);
                }
                true
            }
            Value::String(s) => {
                *s = rng.pick(&STRINGS).to_string();
                true
            }
            Value::Bool(b) => {
                *b = !*b;
                true
            }
            Value::Null => {
                *self = Value::from(*rng.pick(&EDGE_FLOATS));
                true
            }
        }
    }
}

impl Tree for toml::Value {
    fn children(&mut self) -> Vec<&mut Self> {
        match self {
            Self::Array(items) => items.iter_mut().collect(),
            Self::Table(map) => map.iter_mut().map(|(_, v)| v).collect(),
            _ => Vec::new(),
        }
    }

    fn edit(&mut self, rng: &mut Rng) -> bool {
        use toml::Value;
        match self {
            Value::Float(f) => {
                *f = match rng.below(8) {
                    0 => f64::NAN,
                    1 => f64::INFINITY,
                    2 => f64::NEG_INFINITY,
                    _ => edge_float(*f, rng),
                };
                true
            }
            Value::Integer(i) => {
                *self = if rng.one_in(2) {
                    Value::Integer(*rng.pick(&EDGE_INTS))
                } else {
                    Value::Float(edge_float(*i as f64, rng))
                };
                true
            }
            Value::Array(items) => edit_array(items, rng),
            Value::Table(map) => {
                if map.is_empty() {
                    return false;
                }
                let key = map.keys().nth(rng.below(map.len())).cloned();
                if let Some(key) = key {
                    map.remove(&key);
                }
                true
            }
            Value::String(s) => {
                *s = rng.pick(&STRINGS).to_string();
                true
            }
            Value::Boolean(b) => {
                *b = !*b;
                true
            }
            Value::Datetime(_) => false,
        }
    }
}

/// Duplicates an element (up to eight times), removes one, or empties the array.
fn edit_array<T: Clone>(items: &mut Vec<T>, rng: &mut Rng) -> bool {
    if items.is_empty() {
        return false;
    }
    let i = rng.below(items.len());
    match rng.below(4) {
        0 | 1 => {
            let copies = 1 + rng.below(8);
            for _ in 0..copies {
                items.insert(i, items[i].clone());
            }
        }
        2 => {
            items.remove(i);
        }
        _ => items.clear(),
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_mutants_stay_within_the_length_and_mostly_parse() {
        let seed = br#"{"dt":0.01,"bodies":[{"mass":1.0,"name":"a"},{"mass":2.0}],"on":true}"#;
        let mut rng = Rng::new(5);
        let mut parsed = 0;
        for _ in 0..1000 {
            let m = mutate(Format::Json, seed, b"{}", &mut rng, 100);
            assert!(m.len() <= 100);
            parsed += usize::from(serde_json::from_slice::<serde_json::Value>(&m).is_ok());
        }
        // Three in four mutants are tree edits, which print valid JSON.
        assert!(parsed > 600, "{parsed} of 1000 parse");
    }

    #[test]
    fn toml_tree_edits_reach_nan_and_edge_values() {
        let seed = b"[ball]\nmass_kg = 0.027\ncount = 3\n";
        let mut rng = Rng::new(9);
        let mut seen_nan = false;
        let mut seen_inf = false;
        for _ in 0..2000 {
            let m = mutate(Format::Toml, seed, b"", &mut rng, 1000);
            let text = String::from_utf8_lossy(&m);
            seen_nan |= text.contains("nan");
            seen_inf |= text.contains("inf");
        }
        assert!(seen_nan && seen_inf);
    }

    #[test]
    fn the_same_seed_gives_the_same_mutants() {
        let a: Vec<_> = (0..50)
            .scan(Rng::new(3), |r, _| {
                Some(mutate(Format::Bytes, b"abcdef", b"xyz", r, 64))
            })
            .collect();
        let b: Vec<_> = (0..50)
            .scan(Rng::new(3), |r, _| {
                Some(mutate(Format::Bytes, b"abcdef", b"xyz", r, 64))
            })
            .collect();
        assert_eq!(a, b);
    }
}
