//! The scene's tree as `--set` keys walk it: the fields each table of a scene takes, as the
//! scene's own reading (its serde types) lists them, those that the table leaves out
//! included; the place where a key leaves the tree; and the key nearest to a misspelt one.

use std::fmt;
use std::marker::PhantomData;

use serde::Deserialize;
use serde::de::value::{MapDeserializer, SeqDeserializer};
use serde::de::{self, IntoDeserializer, Visitor};

use super::file::{BuiltinFile, DeclaredFile};

/// The largest edit distance at which a key is suggested.
const NEAREST: usize = 2;

/// A field name that no table of a scene has: put into a table, it makes the table's reading
/// refuse it with the list of the fields that the table takes.
const NO_FIELD: &str = "";

/// Where a path of keys lies in a scene's document.
#[derive(Debug, PartialEq)]
pub(super) enum Place {
    /// An entry of the document, or (the last part) a field that its table leaves out.
    Entry,
    /// The path leaves the document at its part `at`: the level above that part has no such
    /// entry. `valid` are the keys of that level ([`keys_of`]).
    Leaves {
        /// Index of the part that the level does not have.
        at: usize,
        /// The keys of the level.
        valid: Vec<String>,
    },
}

/// Where the path `parts` lies in `doc`, a scene's document: the elements of an array are
/// reached by index or, for tables, by their `name`.
pub(super) fn place(doc: &toml::Value, parts: &[&str]) -> Place {
    let mut node = doc;
    for (at, part) in parts.iter().enumerate() {
        let next = match node {
            toml::Value::Table(table) => table.get(*part),
            toml::Value::Array(items) => element(items, part).map(|i| &items[i]),
            _ => None,
        };
        match next {
            Some(found) => node = found,
            None => {
                let valid = keys_of(doc, &parts[..at], node);
                // A field that its table leaves out is set by inserting it.
                if at + 1 == parts.len() && node.is_table() && valid.iter().any(|v| v == part) {
                    return Place::Entry;
                }
                return Place::Leaves { at, valid };
            }
        }
    }
    Place::Entry
}

/// The keys of `node`, the entry at the path `level` of `doc`: for a table, the keys it holds
/// that are not its fields (a tag such as a joint's `type`), then its fields in their declared
/// order, those it leaves out included; for an array, the `name` of each element, or else its
/// index; nothing for a value.
pub(super) fn keys_of(doc: &toml::Value, level: &[&str], node: &toml::Value) -> Vec<String> {
    match node {
        toml::Value::Table(table) => {
            let fields = fields_at(doc, level).unwrap_or_default();
            let others = table.keys().filter(|k| !fields.contains(&k.as_str())).cloned();
            others.chain(fields.iter().map(|f| (*f).to_owned())).collect()
        }
        toml::Value::Array(items) => items
            .iter()
            .enumerate()
            .map(|(i, item)| name_of(item).map_or_else(|| i.to_string(), str::to_owned))
            .collect(),
        _ => Vec::new(),
    }
}

/// The fields that the table at the path `level` of `doc` (a scene's document) takes, in
/// their declared order, as the scene's reading lists them when that table holds a field it
/// does not take; `None` when `level` is no table or its reading lists no fields.
pub(super) fn fields_at(doc: &toml::Value, level: &[&str]) -> Option<&'static [&'static str]> {
    let mut doc = doc.clone();
    let table = node_mut(&mut doc, level)?.as_table_mut()?;
    table.insert(NO_FIELD.to_owned(), toml::Value::Boolean(true));
    let reader = Reader::<Listed>::new(&doc);
    let read = if doc.get("params").is_some() {
        BuiltinFile::deserialize(reader).map(drop)
    } else {
        DeclaredFile::deserialize(reader).map(drop)
    };
    read.err()?.0
}

/// The entry at the path `parts` of `doc`; the elements of an array are reached by index or,
/// for tables, by their `name`.
pub(super) fn node_mut<'a>(
    doc: &'a mut toml::Value,
    parts: &[&str],
) -> Option<&'a mut toml::Value> {
    parts.iter().try_fold(doc, |node, part| match node {
        toml::Value::Table(table) => table.get_mut(*part),
        toml::Value::Array(items) => element(items, part).map(|i| &mut items[i]),
        _ => None,
    })
}

/// The index of the element of `items` that `part` names: its index, or its `name`.
fn element(items: &[toml::Value], part: &str) -> Option<usize> {
    part.parse::<usize>()
        .ok()
        .filter(|&i| i < items.len())
        .or_else(|| items.iter().position(|item| name_of(item) == Some(part)))
}

/// The `name` of an element of an array of tables.
pub(super) fn name_of(item: &toml::Value) -> Option<&str> {
    item.get("name").and_then(toml::Value::as_str)
}

/// The key of `valid` nearest to `name`, when one alone lies within [`NEAREST`] edits of it
/// and nearer than its length.
pub(super) fn nearest<'a>(name: &str, valid: &'a [String]) -> Option<&'a str> {
    let scored: Vec<(usize, &String)> = valid.iter().map(|v| (distance(name, v), v)).collect();
    let best = scored.iter().map(|(d, _)| *d).min()?;
    let mut at_best = scored.iter().filter(|(d, _)| *d == best);
    let (_, key) = at_best.next()?;
    let fits = best <= NEAREST && best < name.chars().count();
    (fits && at_best.next().is_none()).then_some(key.as_str())
}

/// The edit distance between `a` and `b`: insertions, deletions, substitutions and swaps of
/// neighbours, each one edit.
fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[i - 1][j] + 1).min(d[i][j - 1] + 1).min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

/// The error of a reading by [`Reader`]: the fields of the table that met [`NO_FIELD`], as
/// serde's `unknown_field` gives them; `None` for any other refusal.
#[derive(Debug)]
struct Listed(Option<&'static [&'static str]>);

impl fmt::Display for Listed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(fields) => write!(f, "the table's fields are {}", fields.join(", ")),
            None => f.write_str("the scene does not read"),
        }
    }
}

impl std::error::Error for Listed {}

impl de::Error for Listed {
    fn custom<T: fmt::Display>(_: T) -> Self {
        Listed(None)
    }

    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        Listed((field == NO_FIELD).then_some(expected))
    }
}

/// A reader of a TOML value whose errors are `E`, so that a reading's refusal of an unknown
/// field keeps serde's list of the fields (the TOML reader's own errors keep only its text).
struct Reader<'a, E>(&'a toml::Value, PhantomData<E>);

impl<'a, E> Reader<'a, E> {
    fn new(value: &'a toml::Value) -> Self {
        Reader(value, PhantomData)
    }
}

impl<'de, E: de::Error> de::Deserializer<'de> for Reader<'_, E> {
    type Error = E;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, E> {
        match self.0 {
            toml::Value::String(s) => visitor.visit_str(s),
            toml::Value::Integer(i) => visitor.visit_i64(*i),
            toml::Value::Float(x) => visitor.visit_f64(*x),
            toml::Value::Boolean(b) => visitor.visit_bool(*b),
            toml::Value::Datetime(d) => visitor.visit_string(d.to_string()),
            toml::Value::Array(items) => {
                visitor.visit_seq(SeqDeserializer::new(items.iter().map(Reader::new)))
            }
            toml::Value::Table(table) => visitor.visit_map(MapDeserializer::new(
                table.iter().map(|(k, v)| (k.as_str(), Reader::new(v))),
            )),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, E> {
        visitor.visit_some(self)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, E> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, E> {
        match self.0 {
            toml::Value::String(s) => visitor.visit_enum(s.as_str().into_deserializer()),
            _ => self.deserialize_any(visitor),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        unit unit_struct seq tuple tuple_struct map struct identifier ignored_any
    }
}

impl<'de, E: de::Error> IntoDeserializer<'de, E> for Reader<'_, E> {
    type Deserializer = Self;

    fn into_deserializer(self) -> Self {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    #[test]
    fn edit_distances_and_the_nearest_key() {
        assert_eq!(distance("masss", "mass"), 1);
        assert_eq!(distance("mss", "mass"), 1);
        assert_eq!(distance("msas", "mass"), 1);
        assert_eq!(distance("eps_m", "eps_n"), 1);
        assert_eq!(distance("zzz", "dt"), 3);
        let valid: Vec<String> = ["dt", "t_end", "mass", "name"].map(str::to_owned).to_vec();
        assert_eq!(nearest("masss", &valid), Some("mass"));
        assert_eq!(nearest("tend", &valid), Some("t_end"));
        assert_eq!(nearest("zzz", &valid), None);
        // One edit away from a one-letter key is no obvious suggestion; nor is a tie.
        assert_eq!(nearest("x", &["m".to_owned()]), None);
        assert_eq!(nearest("mast", &["mass".to_owned(), "mist".to_owned()]), None);
    }

    /// Every table of every scene of `scenes/` and `scenes/bodies/` lists its fields, so that
    /// no table takes a field the keys do not show or refuses one they show.
    #[test]
    fn every_table_of_the_scenes_lists_its_fields() {
        fn tables(value: &toml::Value, path: Vec<String>, out: &mut Vec<Vec<String>>) {
            let below = |key: String| [path.clone(), vec![key]].concat();
            match value {
                toml::Value::Table(table) => {
                    out.push(path.clone());
                    for (k, v) in table {
                        tables(v, below(k.clone()), out);
                    }
                }
                toml::Value::Array(items) => {
                    for (i, item) in items.iter().enumerate() {
                        let key = name_of(item).map_or_else(|| i.to_string(), str::to_owned);
                        tables(item, below(key), out);
                    }
                }
                _ => {}
            }
        }
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let mut seen = 0;
        for dir in [root.clone(), root.join("bodies")] {
            for entry in std::fs::read_dir(dir).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_none_or(|e| e != "toml") {
                    continue;
                }
                let scene = Scene::from_path(&path).unwrap();
                let doc = toml::Value::try_from(&scene).unwrap();
                let mut found = Vec::new();
                tables(&doc, Vec::new(), &mut found);
                for level in found {
                    let fields =
                        fields_at(&doc, &level.iter().map(String::as_str).collect::<Vec<_>>());
                    assert!(fields.is_some(), "{}: `{}`", path.display(), level.join("."));
                    seen += 1;
                }
            }
        }
        assert!(seen > 50, "{seen} tables");
    }
}
