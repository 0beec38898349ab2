//! Counts on the JSON text, before serde builds any list: every list of a scene (bodies,
//! shapes, parts, joints, trees and their links) counted while the text is read, so an
//! oversized scene is refused before anything is built for it; the text itself bounded.

use std::io::Read;

use serde::de::{DeserializeSeed, IgnoredAny, MapAccess, SeqAccess, Visitor};

use super::*;

/// The entries counted so far, and the first list that went over its limit.
#[derive(Default)]
struct Counts {
    bodies: usize,
    shapes: usize,
    joints: usize,
    materials: usize,
    trees: usize,
    /// Bodies of the current tree.
    links: usize,
    all_links: usize,
    over: Option<SceneError>,
}

/// Which counter an entry adds to.
type Counter = fn(&mut Counts) -> &mut usize;

impl Counts {
    /// Counts one more entry; past the limit, an error that stops the parse (the reason is
    /// kept in `over`).
    fn bump<E: serde::de::Error>(
        &mut self,
        which: Counter,
        path: impl FnOnce() -> String,
        what: &'static str,
        limit: usize,
    ) -> Result<(), E> {
        let n = which(self);
        *n += 1;
        if *n > limit {
            let at_least = *n;
            self.over = Some(SceneError::TooMany {
                path: path(),
                what,
                at_least,
                limit,
            });
            return Err(E::custom("scene list over its limit"));
        }
        Ok(())
    }
}

/// What a list's entries are.
#[derive(Clone, Copy)]
enum List {
    Bodies,
    Joints,
    Materials,
    Trees,
    /// The bodies of tree `k`.
    Links(usize),
    /// The `shapes` of one body.
    Shapes,
}

struct Top<'a>(&'a mut Counts);
struct ListSeed<'a>(&'a mut Counts, List);
struct Entry<'a>(&'a mut Counts, List);
struct ModelSeed<'a>(&'a mut Counts, usize);
/// A shape: counts itself, and a compound's parts (each part's `shape`) besides.
struct ShapeSeed<'a>(&'a mut Counts);
/// A compound's `parts`.
struct PartsSeed<'a>(&'a mut Counts);
/// One part: its `shape`.
struct PartSeed<'a>(&'a mut Counts);

impl<'de> DeserializeSeed<'de> for ShapeSeed<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        self.0.bump(
            |c| &mut c.shapes,
            || "bodies".into(),
            "shapes",
            limits::SHAPES,
        )?;
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for ShapeSeed<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a shape")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            if key == "parts" {
                map.next_value_seed(PartsSeed(&mut *self.0))?;
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for PartsSeed<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for PartsSeed<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a list of parts")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while seq.next_element_seed(PartSeed(&mut *self.0))?.is_some() {}
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for PartSeed<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for PartSeed<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a part")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            if key == "shape" {
                map.next_value_seed(ShapeSeed(&mut *self.0))?;
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for Top<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for Top<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a scene object")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            let list = match key.as_str() {
                "bodies" => List::Bodies,
                "joints" => List::Joints,
                "materials" => List::Materials,
                "articulated" => List::Trees,
                _ => {
                    map.next_value::<IgnoredAny>()?;
                    continue;
                }
            };
            map.next_value_seed(ListSeed(&mut *self.0, list))?;
        }
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for ListSeed<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for ListSeed<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a list")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        if let List::Links(_) = self.1 {
            self.0.links = 0;
        }
        // Each entry counts itself as it starts, so a list far over its limit stops at the
        // first entry past it.
        while seq
            .next_element_seed(Entry(&mut *self.0, self.1))?
            .is_some()
        {}
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for Entry<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let c = self.0;
        let ignore = |d: D| d.deserialize_ignored_any(IgnoredAny).map(|_| ());
        match self.1 {
            List::Bodies | List::Trees => d.deserialize_map(Entry(c, self.1)),
            List::Shapes => {
                c.bump(
                    |c| &mut c.shapes,
                    || "bodies".into(),
                    "shapes",
                    limits::SHAPES,
                )?;
                ignore(d)
            }
            List::Joints => {
                c.bump(
                    |c| &mut c.joints,
                    || "joints".into(),
                    "joints",
                    limits::JOINTS,
                )?;
                ignore(d)
            }
            List::Materials => {
                c.bump(
                    |c| &mut c.materials,
                    || "materials".into(),
                    "materials",
                    limits::MATERIALS,
                )?;
                ignore(d)
            }
            List::Links(k) => {
                c.bump(
                    |c| &mut c.links,
                    || format!("articulated[{k}].model.bodies"),
                    "bodies",
                    limits::TREE_LINKS,
                )?;
                c.bump(
                    |c| &mut c.all_links,
                    || "articulated".into(),
                    "tree bodies",
                    limits::ALL_TREE_LINKS,
                )?;
                ignore(d)
            }
        }
    }
}

impl<'de> Visitor<'de> for Entry<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an object")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let c = self.0;
        let tree = match self.1 {
            List::Bodies => {
                c.bump(
                    |c| &mut c.bodies,
                    || "bodies".into(),
                    "bodies",
                    limits::BODIES,
                )?;
                None
            }
            _ => {
                c.bump(
                    |c| &mut c.trees,
                    || "articulated".into(),
                    "articulated trees",
                    limits::TREES,
                )?;
                Some(c.trees - 1)
            }
        };
        while let Some(key) = map.next_key::<String>()? {
            match (key.as_str(), tree) {
                ("shape", None) => map.next_value_seed(ShapeSeed(&mut *c))?,
                ("shapes", None) => map.next_value_seed(ListSeed(&mut *c, List::Shapes))?,
                ("model", Some(k)) => map.next_value_seed(ModelSeed(&mut *c, k))?,
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for ModelSeed<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for ModelSeed<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a model description")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            if key == "bodies" {
                map.next_value_seed(ListSeed(&mut *self.0, List::Links(self.1)))?;
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(())
    }
}

/// Counts the lists of a scene's JSON text against [`limits`] without building them, and
/// bounds the text's size. Text that is not JSON passes: serde's full parse reports it.
pub(crate) fn check_counts(text: &str) -> Result<(), SceneError> {
    if text.len() > limits::SCENE_BYTES {
        return Err(SceneError::TooLarge {
            bytes: text.len() as u64,
            limit: limits::SCENE_BYTES as u64,
        });
    }
    let mut counts = Counts::default();
    let mut de = serde_json::Deserializer::from_str(text);
    let _ = Top(&mut counts).deserialize(&mut de);
    match counts.over {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// A reader that keeps what it reads, up to [`limits::SCENE_BYTES`].
struct Keep<R> {
    inner: R,
    kept: Vec<u8>,
    too_large: bool,
}

impl<R: Read> Read for Keep<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        if self.kept.len() + n > limits::SCENE_BYTES {
            self.too_large = true;
            return Err(std::io::Error::other("scene text over its size limit"));
        }
        self.kept.extend_from_slice(&buf[..n]);
        Ok(n)
    }
}

/// Reads a scene's text from `reader` (named `source` in errors), counting its lists while
/// reading: stops at the first list over its limit ([`SceneError::TooMany`]) or past
/// [`limits::SCENE_BYTES`] ([`SceneError::TooLarge`]), so neither a huge file nor an
/// endless stream is held in memory.
pub(crate) fn read_bounded(reader: impl Read, source: &str) -> Result<String, SceneError> {
    let mut keep = Keep {
        inner: reader,
        kept: Vec::new(),
        too_large: false,
    };
    let mut counts = Counts::default();
    let parsed = {
        let mut de = serde_json::Deserializer::from_reader(std::io::BufReader::new(&mut keep));
        Top(&mut counts)
            .deserialize(&mut de)
            .and_then(|()| de.end())
    };
    if let Some(e) = counts.over {
        return Err(e);
    }
    let too_large = || SceneError::TooLarge {
        bytes: limits::SCENE_BYTES as u64 + 1,
        limit: limits::SCENE_BYTES as u64,
    };
    let io = |source_error| SceneError::Io {
        path: source.to_string(),
        source: source_error,
    };
    if keep.too_large {
        return Err(too_large());
    }
    if let Err(e) = parsed {
        if e.is_io() {
            return Err(io(std::io::Error::other(e.to_string())));
        }
        // Not JSON of the scene's shape: read the rest (bounded) so that the full parse
        // reports the error in its own words.
        let mut rest = Vec::new();
        let read = keep.read_to_end(&mut rest);
        if keep.too_large {
            return Err(too_large());
        }
        read.map_err(io)?;
    }
    String::from_utf8(keep.kept)
        .map_err(|e| SceneError::Syntax(format!("scene text is not UTF-8: {e}")))
}

/// Reads a scene file with [`read_bounded`]; a file larger than [`limits::SCENE_BYTES`] is
/// refused before it is read.
pub(crate) fn read_file(path: &str) -> Result<String, SceneError> {
    let io = |source| SceneError::Io {
        path: path.to_string(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let bytes = file.metadata().map_err(io)?.len();
    if bytes > limits::SCENE_BYTES as u64 {
        return Err(SceneError::TooLarge {
            bytes,
            limit: limits::SCENE_BYTES as u64,
        });
    }
    read_bounded(file, path)
}
