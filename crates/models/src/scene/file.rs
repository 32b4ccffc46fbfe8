//! The two forms of a scene file, a report model's (with `[params]`) and a declared
//! mechanism's, as serde structs; and the reader's errors turned into ones that name the
//! field at fault.

use serde::{Deserialize, Serialize};

use super::labels::{self, FileImpulses};
use super::{Scene, StopRule};
use crate::bodies::{
    AutoContacts, BodySpec, ContactSet, ContactSpec, FillSpec, ForceSpec, JointSpec, SystemSpec,
};
use crate::{
    AnyModel, BallParams, CamParams, ModelError, ModelKind, ModelParams, PainleveParams,
    SliderCrankIdealParams, SliderCrankParams, WoodpeckerParams,
};
use moreau_stepper::{Impulses, SolverChoice};

fn one() -> usize {
    1
}

fn yes() -> bool {
    true
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_true(b: &bool) -> bool {
    *b
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// A report model's scene as written in TOML.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BuiltinFile {
    dt: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    t_start: f64,
    t_end: f64,
    #[serde(default = "one")]
    record_every: usize,
    #[serde(default)]
    solver: SolverChoice,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    stop_at: Option<StopRule>,
    #[serde(default, skip_serializing_if = "is_false")]
    projection: bool,
    #[serde(default, skip_serializing_if = "is_zero")]
    inexact_residual: f64,
    params: ModelParams,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    impulses: Option<Impulses>,
}

/// A declared mechanism's scene as written in TOML: the scene's keys and the declaration's.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DeclaredFile {
    dt: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    t_start: f64,
    t_end: f64,
    #[serde(default = "one")]
    record_every: usize,
    #[serde(default)]
    solver: SolverChoice,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    stop_at: Option<StopRule>,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    projection: bool,
    #[serde(default, skip_serializing_if = "is_zero")]
    inexact_residual: f64,
    gravity: [f64; 2],
    bodies: Vec<BodySpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    joints: Vec<JointSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    forces: Vec<ForceSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    contacts: Vec<ContactSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    contacts_auto: Option<AutoContacts>,
    #[serde(default, skip_serializing_if = "ContactSet::is_fixed")]
    contact_set: ContactSet,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    fill: Vec<FillSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    impulses: Option<FileImpulses>,
}

impl From<BuiltinFile> for Scene {
    fn from(f: BuiltinFile) -> Self {
        Scene {
            dt: f.dt,
            t_start: f.t_start,
            t_end: f.t_end,
            record_every: f.record_every,
            solver: f.solver,
            stop_at: f.stop_at,
            projection: f.projection,
            inexact_residual: f.inexact_residual,
            params: f.params,
            impulses: f.impulses,
        }
    }
}

impl DeclaredFile {
    /// The scene, with the impulses that the file names resolved against the mechanism it
    /// declares ([`labels`]).
    ///
    /// # Errors
    /// The errors of [`FileImpulses::resolve`].
    pub(super) fn into_scene(mut self) -> Result<Scene, ModelError> {
        let named = self.impulses.take();
        let spec = SystemSpec {
            gravity: self.gravity,
            bodies: self.bodies,
            joints: self.joints,
            forces: self.forces,
            contacts: self.contacts,
            contacts_auto: self.contacts_auto,
            contact_set: self.contact_set,
            fill: self.fill,
        };
        let mut scene = Scene {
            dt: self.dt,
            t_start: self.t_start,
            t_end: self.t_end,
            record_every: self.record_every,
            solver: self.solver,
            stop_at: self.stop_at,
            projection: self.projection,
            inexact_residual: self.inexact_residual,
            params: ModelParams::Declared(Box::new(spec)),
            impulses: None,
        };
        if let Some(named) = named {
            scene.impulses = Some(named.resolve_in(&scene)?);
        }
        Ok(scene)
    }
}

impl Serialize for Scene {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match &self.params {
            ModelParams::Declared(spec) => DeclaredFile {
                dt: self.dt,
                t_start: self.t_start,
                t_end: self.t_end,
                record_every: self.record_every,
                solver: self.solver,
                stop_at: self.stop_at.clone(),
                projection: self.projection,
                inexact_residual: self.inexact_residual,
                gravity: spec.gravity,
                bodies: spec.bodies.clone(),
                joints: spec.joints.clone(),
                forces: spec.forces.clone(),
                contacts: spec.contacts.clone(),
                contacts_auto: spec.contacts_auto.clone(),
                contact_set: spec.contact_set,
                fill: spec.fill.clone(),
                impulses: self.impulses.as_ref().map(FileImpulses::of_ids),
            }
            .serialize(serializer),
            params => BuiltinFile {
                dt: self.dt,
                t_start: self.t_start,
                t_end: self.t_end,
                record_every: self.record_every,
                solver: self.solver,
                stop_at: self.stop_at.clone(),
                projection: self.projection,
                inexact_residual: self.inexact_residual,
                params: params.clone(),
                impulses: self.impulses.clone(),
            }
            .serialize(serializer),
        }
    }
}

/// The scene as TOML: its fields as serde writes them, then the table `[impulses]`, whose
/// contacts (thousands in a settled pile) and joint rows are written one per line so that a
/// reader can find and edit one; a declared mechanism's by name ([`labels`]), so that they
/// still name their contacts when bodies come or go before others.
///
/// # Errors
/// [`ModelError::Unwritable`] for what TOML cannot hold; a declared mechanism's impulses that
/// name no contact of its own, or the errors of building it.
pub(super) fn to_toml(scene: &Scene) -> Result<String, ModelError> {
    let unwritable = |e: toml::ser::Error| ModelError::Unwritable { message: e.to_string() };
    let Some(impulses) = &scene.impulses else {
        return toml::to_string(scene).map_err(unwritable);
    };
    let file = match &scene.params {
        ModelParams::Declared(_) => match scene.build()? {
            AnyModel::Declared(mb) => labels::named(&mb, impulses)?,
            _ => unreachable!("a declaration builds a declared mechanism"),
        },
        _ => FileImpulses::of_ids(impulses),
    };
    let mut text =
        toml::to_string(&Scene { impulses: None, ..scene.clone() }).map_err(unwritable)?;
    text.push_str("\n[impulses]\n");
    fn value<T: Serialize>(v: &T) -> Result<toml::Value, ModelError> {
        toml::Value::try_from(v).map_err(|e| ModelError::Unwritable { message: e.to_string() })
    }
    if !file.contacts.is_empty() {
        text.push_str("contacts = [\n");
        for contact in &file.contacts {
            text.push_str(&format!("    {},\n", value(contact)?));
        }
        text.push_str("]\n");
    }
    if !file.joints.is_empty() {
        text.push_str("joints = [\n");
        for row in &file.joints {
            text.push_str(&format!("    {},\n", value(row)?));
        }
        text.push_str("]\n");
    }
    Ok(text)
}

impl<'de> Deserialize<'de> for Scene {
    /// Reads either form: with a `params` table the report model's, otherwise the declared.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let value = toml::Value::deserialize(deserializer)?;
        if value.get("params").is_some() {
            BuiltinFile::deserialize(value).map(Scene::from).map_err(D::Error::custom)
        } else {
            let file = DeclaredFile::deserialize(value).map_err(D::Error::custom)?;
            file.into_scene().map_err(D::Error::custom)
        }
    }
}

/// The required keys of a scene's top level, in either form.
const REQUIRED: [&str; 4] = ["dt", "t_end", "gravity", "bodies"];

/// The refusal of a scene that lacks one of its top level's required keys (which `has` says it
/// does not have): it names no field, since the reader points at the document's start, its
/// first key, which is not at fault.
fn missing_at_top(error: &toml::de::Error, has: impl Fn(&str) -> bool) -> Option<ModelError> {
    let missing = missing_field_name(error.message())?;
    (REQUIRED.contains(&missing.as_str()) && !has(&missing)).then(|| ModelError::Parse {
        path: None,
        field: None,
        message: error.message().trim().to_owned(),
    })
}

/// Turns the TOML reader's error into a [`ModelError::Parse`] that names the field.
pub(super) fn parse_error(text: &str, error: &toml::de::Error) -> ModelError {
    let top = |k: &str| toml::from_str::<toml::Table>(text).is_ok_and(|t| t.contains_key(k));
    if let Some(refusal) = missing_at_top(error, top) {
        return refusal;
    }
    let located = error.span().and_then(|span| locate_key(text, span.start));
    if let Some(field) = located {
        return ModelError::Parse { path: None, field: Some(field), message: error.to_string() };
    }
    // Errors inside `[params]` come from a buffered, internally tagged enum and point at the
    // table header only; read the table again as the named model's parameters to find the key.
    if let Some((field, message)) = diagnose_params(text) {
        return ModelError::Parse {
            path: None,
            field: Some(field),
            message: both(error.message(), message),
        };
    }
    ModelError::Parse { path: None, field: None, message: error.to_string() }
}

/// The reader's message, then the one found by reading the field again unless it says the same.
fn both(reader: &str, found: String) -> String {
    if reader.trim() == found.trim() { found } else { format!("{reader}\n{found}") }
}

/// The dotted key written on the line that holds byte `offset`, with its table header.
fn locate_key(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("").trim();
    if line.starts_with('[') || !line.contains('=') {
        return None;
    }
    let key = unquote(line.split('=').next()?.trim());
    let before = &text[..line_start];
    let header = before.lines().rev().map(str::trim).find(|l| l.starts_with('['));
    Some(match header {
        // An element of an array of tables is named by its `name`, as under `--set`, or else
        // by its index.
        Some(h) if h.starts_with("[[") => {
            let array = unquote(h.trim_matches(|c| c == '[' || c == ']').trim());
            let elements = before.lines().filter(|l| l.trim() == h).count();
            let start = before.rfind(h).map_or(0, |i| i + h.len());
            let rest = &text[start..];
            let end = rest.lines().position(|l| l.trim_start().starts_with('['));
            let name = rest
                .lines()
                .take(end.unwrap_or(usize::MAX))
                .filter_map(|l| l.trim().strip_prefix("name"))
                .find_map(|l| l.trim().strip_prefix('='))
                .map(|v| unquote(v.split('#').next().unwrap_or("").trim()));
            let element = name.unwrap_or_else(|| elements.saturating_sub(1).to_string());
            format!("{array}.{element}.{key}")
        }
        Some(h) => format!("{}.{key}", unquote(h.trim_matches(|c| c == '[' || c == ']').trim())),
        None => key,
    })
}

fn unquote(s: &str) -> String {
    s.split('.')
        .map(|p| p.trim().trim_matches('"').trim_matches('\''))
        .collect::<Vec<_>>()
        .join(".")
}

/// Reads `[params]` again as the named model's own parameter struct, whose errors carry
/// spans; returns the offending field and the reader's message.
fn diagnose_params(text: &str) -> Option<(String, String)> {
    let doc: toml::Table = toml::from_str(text).ok()?;
    let mut params = doc.get("params")?.as_table()?.clone();
    let kind: ModelKind = params.remove("model")?.as_str()?.parse().ok()?;
    let sub = toml::to_string(&params).ok()?;
    let error = match kind {
        ModelKind::Ball => toml::from_str::<BallParams>(&sub).err(),
        ModelKind::Woodpecker => toml::from_str::<WoodpeckerParams>(&sub).err(),
        ModelKind::SliderCrank => toml::from_str::<SliderCrankParams>(&sub).err(),
        ModelKind::SliderCrankIdeal => toml::from_str::<SliderCrankIdealParams>(&sub).err(),
        ModelKind::Cam => toml::from_str::<CamParams>(&sub).err(),
        ModelKind::Painleve => toml::from_str::<PainleveParams>(&sub).err(),
        ModelKind::Declared => None,
    }?;
    let message = error.message().to_owned();
    let field = match error.span().and_then(|s| locate_key(&sub, s.start)) {
        Some(f) => format!("params.{f}"),
        None => match unknown_field_name(&message) {
            Some(f) => format!("params.{f}"),
            None => "params".to_owned(),
        },
    };
    Some((field, message))
}

/// The name in "unknown field `name`, expected ...".
fn unknown_field_name(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    Some(rest[..rest.find('`')?].to_owned())
}

/// The keys that tag a table's kind (`type = "disk"`, `kind = "rotate"`).
const TAGS: [&str; 2] = ["type", "kind"];

/// The entry at the path `path` below `value`: table keys, or array indices.
fn entry<'a>(value: &'a toml::Value, path: &[String]) -> Option<&'a toml::Value> {
    path.iter().try_fold(value, |node, part| match node {
        toml::Value::Table(t) => t.get(part),
        toml::Value::Array(a) => part.parse::<usize>().ok().and_then(|i| a.get(i)),
        _ => None,
    })
}

/// The entry at the path `path` below `value`, to change.
fn entry_mut<'a>(value: &'a mut toml::Value, path: &[String]) -> Option<&'a mut toml::Value> {
    path.iter().try_fold(value, |node, part| match node {
        toml::Value::Table(t) => t.get_mut(part),
        toml::Value::Array(a) => part.parse::<usize>().ok().and_then(|i| a.get_mut(i)),
        _ => None,
    })
}

/// The keys of a table, or the indices of an array.
fn children(node: &toml::Value) -> Vec<String> {
    match node {
        toml::Value::Table(t) => t.keys().cloned().collect(),
        toml::Value::Array(a) => (0..a.len()).map(|i| i.to_string()).collect(),
        _ => Vec::new(),
    }
}

/// The name in "missing field `name`".
fn missing_field_name(message: &str) -> Option<String> {
    let rest = message.trim_start().strip_prefix("missing field `")?;
    Some(rest[..rest.find('`')?].to_owned())
}

/// The path below `item` (a table that does not read as a `T`, with the reader's `message`)
/// of the entry at fault, down through its tables and arrays: at each level the key (or
/// element) whose removal lets `item` read, or leaves only that key missing; an array that
/// the removal of any of several elements mends (one too long) is itself at fault. For a missing
/// field, the table that lacks it. Empty when no single entry is at fault. A tagged table's
/// tag (`type`, `kind`) is read before its other keys, so its removal always leaves it
/// missing: it is at fault only when the message is about a variant.
fn culprit<T: serde::de::DeserializeOwned>(item: &toml::Value, message: &str) -> Vec<String> {
    let reads = |v: toml::Value| T::deserialize(v).map(drop).map_err(|e| e.message().to_owned());
    if let Some(missing) = missing_field_name(message) {
        return lacking(item, &missing, message, reads);
    }
    let about_variant = message.contains("variant");
    let mut path: Vec<String> = Vec::new();
    let mends = |path: &[String], key: &str| {
        let mut without = item.clone();
        match entry_mut(&mut without, path) {
            Some(toml::Value::Table(t)) => drop(t.remove(key)),
            Some(toml::Value::Array(a)) => drop(a.remove(key.parse::<usize>().unwrap_or(0))),
            _ => return false,
        }
        match reads(without) {
            Ok(()) => true,
            Err(e) => e.trim() == format!("missing field `{key}`"),
        }
    };
    while let Some(node) = entry(item, &path) {
        let keys = children(node);
        let mut mending = keys
            .iter()
            .filter(|key| !(node.is_table() && TAGS.contains(&key.as_str()) && !about_variant))
            .filter(|key| mends(&path, key));
        let Some(first) = mending.next() else { break };
        // An array mended by the removal of any of several elements (one too long) is itself
        // at fault, not one of its elements.
        if node.is_array() && mending.next().is_some() {
            break;
        }
        path.push(first.clone());
    }
    path
}

/// The path below `item` of the table that lacks the field `missing`: the first, in the order
/// of the document, into which the field put changes the reader's `message` to another than
/// that the table has no such field.
fn lacking(
    item: &toml::Value,
    missing: &str,
    message: &str,
    reads: impl Fn(toml::Value) -> Result<(), String>,
) -> Vec<String> {
    let mut queue = vec![Vec::<String>::new()];
    while let Some(path) = queue.pop() {
        let Some(node) = entry(item, &path) else { continue };
        if let Some(table) = node.as_table()
            && !table.contains_key(missing)
        {
            let mut with = item.clone();
            if let Some(toml::Value::Table(t)) = entry_mut(&mut with, &path) {
                t.insert(missing.to_owned(), toml::Value::Integer(0));
            }
            let changed = match reads(with) {
                Ok(()) => true,
                Err(e) => {
                    e.trim() != message.trim()
                        && !e.trim_start().starts_with(&format!("unknown field `{missing}`"))
                }
            };
            if changed {
                return path;
            }
        }
        // Depth first, in the document's order.
        for key in children(node).into_iter().rev() {
            queue.push([path.clone(), vec![key]].concat());
        }
    }
    Vec::new()
}

/// Turns the TOML reader's error on a declared scene into a [`ModelError::Parse`] that names
/// the field by its `--set` path: each element of the arrays of tables is read again alone to
/// find the one at fault (the reader's positions name the array, not the element, and the
/// tagged tables of joints and forces lose them).
pub(super) fn declared_parse_error(
    text: &str,
    table: &toml::Table,
    error: &toml::de::Error,
) -> ModelError {
    fn first_error<T: serde::de::DeserializeOwned>(
        table: &toml::Table,
        key: &str,
    ) -> Option<(String, String)> {
        let read = |item: &toml::Value, at: Vec<String>| {
            let e = T::deserialize(item.clone()).err()?;
            let message = e.message().to_owned();
            let mut field = at;
            field.extend(culprit::<T>(item, &message));
            if let Some(f) = unknown_field_name(&message)
                && field.last() != Some(&f)
            {
                field.push(f);
            }
            Some((field.join("."), message))
        };
        match table.get(key)? {
            // A table such as `[contacts_auto]` is read as one.
            item @ toml::Value::Table(_) => read(item, vec![key.to_owned()]),
            toml::Value::Array(items) => items.iter().enumerate().find_map(|(i, item)| {
                let name = item.get("name").and_then(toml::Value::as_str);
                let element = name.map_or_else(|| i.to_string(), str::to_owned);
                read(item, vec![key.to_owned(), element])
            }),
            _ => None,
        }
    }
    let found = first_error::<BodySpec>(table, "bodies")
        .or_else(|| first_error::<JointSpec>(table, "joints"))
        .or_else(|| first_error::<ForceSpec>(table, "forces"))
        .or_else(|| first_error::<ContactSpec>(table, "contacts"))
        .or_else(|| first_error::<AutoContacts>(table, "contacts_auto"))
        .or_else(|| first_error::<FillSpec>(table, "fill"));
    // A field missing from the top level has no table to name: the reader points at the
    // document's start, its first key.
    if found.is_none()
        && let Some(top) = missing_at_top(error, |k| table.contains_key(k))
    {
        return top;
    }
    match found {
        Some((field, message)) => ModelError::Parse {
            path: None,
            field: Some(field),
            message: both(error.message(), message),
        },
        // An error outside the arrays of tables keeps the reader's position.
        None => ModelError::Parse {
            path: None,
            field: error.span().and_then(|span| locate_key(text, span.start)),
            message: error.to_string(),
        },
    }
}
