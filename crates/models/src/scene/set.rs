//! Single values of a scene by their dotted keys, as given on a command line by
//! `--set key=value`: the keys a scene accepts, the entries a key reaches and the change of
//! one value, with the scene validated again.

use moreau_stepper::{Impulses, UnknownSolver};

use super::labels::{self, FileImpulses};
use super::{Scene, tree};
use crate::{AnyModel, ModelError, ModelKind, ModelParams};

impl Scene {
    /// The keys the scene writes, which [`Self::set`] accepts: the scene's keys (`dt`,
    /// `t_end`, `record_every`, `solver`, ...) and then the model's parameters without the
    /// `params.` prefix (`m`, `eps_n`, `init.y0`, `beak.mu`, ...), or a declared mechanism's
    /// (`bodies.<name>.velocity`, `joints.<name>.anchor_a`, `contacts.<name>.mu`, ...; an
    /// array's entry as `bodies.<name>.velocity.0`).
    /// [`Self::set`] also takes the optional fields that the scene's tables leave out
    /// (`projection`, `bodies.<name>.density`, `joints.<name>.angle`), whole tables and, in a
    /// declared scene, whole arrays.
    pub fn keys(&self) -> Vec<String> {
        self.leaves().into_iter().map(|(display, _)| display).collect()
    }

    /// Leaves of the scene's TOML tree: (display key, full path).
    fn leaves(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let value = match toml::Value::try_from(self) {
            Ok(v) => v,
            Err(_) => return out,
        };
        let mut scene_keys = Vec::new();
        let mut param_keys = Vec::new();
        collect_leaves(&value, "", &mut |path| {
            if path == "params.model" || path == "solver.kind" {
                return;
            }
            match path.strip_prefix("params.") {
                Some(rest) => param_keys.push((rest.to_owned(), path.to_owned())),
                None => scene_keys.push((path.to_owned(), path.to_owned())),
            }
        });
        out.push(("solver".to_owned(), "solver".to_owned()));
        out.extend(scene_keys);
        out.extend(param_keys);
        out
    }

    /// The keys of the top level of a report model's scene, `doc`: the scene's own keys and
    /// the fields it leaves out (`stop_at`, `projection`, ...), then the parameters' keys and
    /// the fields they leave out.
    fn top_keys(&self, doc: &toml::Value) -> Vec<String> {
        let left_out = |level: &[&str], tag: &str| -> Vec<String> {
            let fields = tree::fields_at(doc, level).unwrap_or_default();
            let table =
                level.iter().try_fold(doc, |v, k| v.get(*k)).and_then(toml::Value::as_table);
            let present = |f: &&str| table.is_some_and(|t| t.contains_key(*f));
            fields.iter().filter(|f| **f != tag && !present(f)).map(|f| (*f).to_owned()).collect()
        };
        let (params, scene): (Vec<_>, Vec<_>) =
            self.leaves().into_iter().partition(|(_, full)| full.starts_with("params."));
        let mut out: Vec<String> = scene.into_iter().map(|(display, _)| display).collect();
        out.extend(left_out(&[], "params"));
        out.extend(params.into_iter().map(|(display, _)| display));
        out.extend(left_out(&["params"], "model"));
        out
    }

    /// The full dotted paths of the entries that [`Self::set`] with `key` changes: `solver`
    /// for `solver`, `params.init.y0` for `init.y0` or `y0`, and on the woodpecker
    /// `params.beak.mu`, `params.lower.mu` and `params.upper.mu` for `mu`. Two keys set the
    /// same entry exactly when their targets share a path.
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] when `key` names no entry of the scene nor a field that one
    /// of its tables leaves out, with the level where it leaves the scene's tree, the keys of
    /// that level and the nearest of them.
    pub fn targets(&self, key: &str) -> Result<Vec<String>, ModelError> {
        if key == "solver" {
            return Ok(vec!["solver".to_owned()]);
        }
        let leaves = self.leaves();
        let short = key.strip_prefix("params.").unwrap_or(key);
        let exact: Vec<&String> =
            leaves.iter().filter(|(d, full)| d == short || full == key).map(|(_, f)| f).collect();
        let targets: Vec<&String> = if exact.is_empty() {
            let suffix = format!(".{short}");
            leaves.iter().filter(|(d, _)| d.ends_with(&suffix)).map(|(_, f)| f).collect()
        } else {
            exact
        };
        if !targets.is_empty() && !key.is_empty() {
            return Ok(targets.into_iter().cloned().collect());
        }
        // An entry that is no leaf (a whole table, an array's element as
        // `bodies.block.position.1`) or an optional field that its table leaves out
        // (`bodies.block.density`) is found in the scene's tree. A report model's parameters
        // lie under `params`, and their keys leave it out.
        let doc =
            toml::Value::try_from(self).unwrap_or_else(|_| toml::Value::Table(toml::Table::new()));
        let declared = self.kind() == ModelKind::Declared;
        let shown: Vec<&str> = if declared { key } else { short }.split('.').collect();
        let under_params = !declared && !is_scene_key(&doc, shown[0]);
        let parts: Vec<&str> = if under_params { vec!["params"] } else { Vec::new() }
            .into_iter()
            .chain(shown.iter().copied())
            .collect();
        let place = match tree::place(&doc, &parts) {
            // The model is chosen by the scene, not set.
            tree::Place::Entry if parts == ["params", "model"] => {
                tree::Place::Leaves { at: 1, valid: Vec::new() }
            }
            place => place,
        };
        let (at, valid) = match place {
            tree::Place::Entry => {
                // An element of an array of tables given by its index (`bodies.1.mass`) is
                // named by its `name`, as the leaves name it, so that two keys for one entry
                // are seen as such.
                let named = named_path(&doc, &parts.join("."));
                return Ok(match leaves.iter().find(|(_, full)| *full == named) {
                    Some((_, full)) => vec![full.clone()],
                    None => vec![named],
                });
            }
            tree::Place::Leaves { at, valid } => (at - usize::from(under_params), valid),
        };
        Err(self.unknown_key(&doc, key, &shown, at, valid))
    }

    /// The refusal of `key`, whose parts `shown` (without `params.` on a report model) leave
    /// the scene's tree, `doc`, at the part `at`, below a level whose keys are `valid`.
    fn unknown_key(
        &self,
        doc: &toml::Value,
        key: &str,
        shown: &[&str],
        at: usize,
        valid: Vec<String>,
    ) -> ModelError {
        // The top of a report model shows its parameters' keys whole, without `params.`.
        let top = self.kind() != ModelKind::Declared && at == 0;
        let valid = if top { self.top_keys(doc) } else { valid };
        let (level, name, rest) = (shown[..at].join("."), shown[at], &shown[at + 1..]);
        // A field that the level leaves out, with parts below it, is no misspelling.
        let suggestion = if valid.iter().any(|v| v == name) {
            None
        } else {
            let whole = |near: &str| {
                let level = (!level.is_empty()).then_some(level.as_str());
                let parts = level.into_iter().chain([near]).chain(rest.iter().copied());
                parts.collect::<Vec<_>>().join(".")
            };
            tree::nearest(name, &valid).map(whole).or_else(|| {
                // A report model's parameter given whole with a misspelt table (`initt.y0`).
                let joined = shown.join(".");
                (top && !rest.is_empty())
                    .then(|| tree::nearest(&joined, &valid))
                    .flatten()
                    .map(str::to_owned)
            })
        };
        ModelError::UnknownKey {
            key: key.to_owned(),
            level,
            name: name.to_owned(),
            valid,
            suggestion,
        }
    }

    /// Sets one value, as given on a command line by `--set key=value`.
    ///
    /// `key` is one of [`Self::keys`] (with or without the `params.` prefix) or a last part
    /// of one or more of them: `mu` on the woodpecker sets `beak.mu`, `lower.mu` and
    /// `upper.mu`; `v0` sets `init.v0`. `solver` takes a solver name (`auto`, `lemke`, `pgs`,
    /// `enum`). The value is parsed as the type the key already has (a number and a table
    /// stand for each other, as a load is either), and the whole scene is read and validated
    /// again; on any error the scene is left unchanged. Changes that are only valid together
    /// (a body moved with the joint anchor that holds it) are made by [`Self::edit`].
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] listing the accepted keys; [`ModelError::BadValue`] naming the
    /// key when the value does not parse or is out of range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), ModelError> {
        let mut edit = self.clone().edit();
        edit.set(key, value)?;
        *self = edit.finish()?;
        Ok(())
    }

    /// Starts a sequence of [`SceneEdit::set`]s that is validated as a whole when it ends,
    /// so that changes which are only valid together can be made one key at a time.
    ///
    /// ```
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// use moreau_models::Scene;
    ///
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/bodies/pendulum-wall.toml");
    /// let scene = Scene::from_toml_str(&std::fs::read_to_string(path)?)?;
    /// // The bob hangs a metre below the hinge; it moves with the joint's anchor on it.
    /// let mut edit = scene.edit();
    /// edit.set("bodies.bob.position", "[0.0, -1.0]")?;
    /// edit.set("joints.hinge.anchor_b", "[0.0, 1.0]")?;
    /// let scene = edit.finish()?;
    /// assert!(scene.to_toml_string()?.contains("anchor_b = [0.0, 1.0]"));
    /// # Ok(())
    /// # }
    /// ```
    pub fn edit(self) -> SceneEdit {
        let named = self.named_impulses();
        SceneEdit { scene: self, count: 0, invalid: None, named }
    }

    /// A declared mechanism's impulses as they are, and by the names of its contacts and
    /// joint rows; `None` for a scene without impulses or whose names cannot be had.
    fn named_impulses(&self) -> Option<(Impulses, FileImpulses)> {
        let impulses = self.impulses.as_ref()?;
        let ModelParams::Declared(_) = &self.params else { return None };
        let AnyModel::Declared(mb) = self.build().ok()? else { return None };
        Some((impulses.clone(), labels::named(&mb, impulses).ok()?))
    }

    /// The scene with `key` set to `value`, read again but not validated.
    fn assigned(&self, key: &str, value: &str) -> Result<Scene, ModelError> {
        let bad = |reason: String| bad_value(key, value, reason);
        if key == "solver" {
            // A name (`pgs`, with its defaults), or the scene file's table
            // (`{ kind = "pgs", omega = 1.2 }`).
            let solver = if value.trim_start().starts_with('{') {
                toml::from_str(&format!("solver = {value}"))
                    .and_then(|table: toml::Table| table["solver"].clone().try_into())
                    .map_err(|e| bad(format!("not a solver table: {}", reason_of(&e))))?
            } else {
                value.trim().parse().map_err(|e: UnknownSolver| {
                    bad(format!("{e}, or a table as in a scene file: {{ kind = \"pgs\", ... }}"))
                })?
            };
            return Ok(Scene { solver, ..self.clone() });
        }
        let targets = self.targets(key)?;
        let mut doc = toml::Value::try_from(self).map_err(|e| bad(e.to_string()))?;
        for path in &targets {
            match leaf_mut(&mut doc, path) {
                Some(slot) => *slot = parse_like(slot, value).map_err(bad)?,
                None => {
                    let (parent, last) = path.rsplit_once('.').unwrap_or(("", path));
                    let table = leaf_mut(&mut doc, parent)
                        .and_then(toml::Value::as_table_mut)
                        .ok_or_else(|| bad(format!("no value at `{path}`")))?;
                    table.insert(last.to_owned(), parse_any(value));
                }
            }
        }
        doc.try_into().map_err(|e: toml::de::Error| bad(reason_of(&e)))
    }
}

/// Changes to a scene made one key at a time, as [`Scene::set`] makes them, but validated
/// as a whole by [`Self::finish`]: a body moved together with the joint anchor that holds
/// it, a shape resized together with the body's inertia. Each change is read at once (an
/// unknown key or a value that does not parse is refused by [`Self::set`]); the scene in
/// between may be invalid.
#[derive(Debug)]
pub struct SceneEdit {
    /// The scene as changed so far.
    scene: Scene,
    /// The changes made so far.
    count: usize,
    /// The change after which the scene became invalid, counted from 0, and why, when the
    /// scene has not become valid again since.
    invalid: Option<(usize, ModelError)>,
    /// A declared mechanism's impulses before the changes, by identity and by name: a change
    /// that adds or removes shapes renumbers the contacts after them, whose impulses then
    /// follow their names.
    named: Option<(Impulses, FileImpulses)>,
}

impl SceneEdit {
    /// The scene as changed so far, not yet validated: the keys a next change may name are
    /// its [`Scene::keys`] and its [`Scene::targets`].
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Sets one value as [`Scene::set`] does, leaving the validation of the whole to
    /// [`Self::finish`].
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] listing the accepted keys; [`ModelError::BadValue`] naming the
    /// key when the value does not parse or the scene does not read with it. The edit is left
    /// as it was.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), ModelError> {
        let scene = self.scene.assigned(key, value)?;
        // A refusal that already names a key and its value is given as it is; one of the key
        // itself gives only its reason.
        let refusal = scene.validate().err().map(|e| match e {
            ModelError::BadValue { .. } => e,
            ModelError::InvalidParameter { ref field, ref reason, .. } if field == key => {
                bad_value(key, value, reason.clone())
            }
            other => bad_value(key, value, other.to_string()),
        });
        self.invalid = match (self.invalid.take(), refusal) {
            (_, None) => None,
            (Some(earlier), Some(_)) => Some(earlier),
            (None, Some(e)) => Some((self.count, e)),
        };
        self.scene = scene;
        self.count += 1;
        Ok(())
    }

    /// The change after which the scene became invalid and stayed so, counted from 0 in
    /// the order of [`Self::set`]; `None` while the scene as changed so far is valid.
    pub fn invalid_since(&self) -> Option<usize> {
        self.invalid.as_ref().map(|(at, _)| *at)
    }

    /// The changed scene, when it is valid.
    ///
    /// A declared mechanism's impulses (a scene continued from a run's end) are taken by the
    /// names of their contacts and joint rows in the scene as it was, and given to the same
    /// names in the changed scene: a change that adds a shape to one body renumbers the
    /// contacts of the bodies after it, and their impulses follow them. A change of the
    /// impulses themselves is kept as it is made.
    ///
    /// # Errors
    /// When the scene is not valid, the refusal of the scene as the change
    /// [`Self::invalid_since`] names left it; [`ModelError::BadValue`] (key
    /// `impulses.contacts.<k>` or `impulses.joints.<k>`) for an impulse whose contact or
    /// joint row the changes removed.
    pub fn finish(self) -> Result<Scene, ModelError> {
        if let Some((_, refusal)) = self.invalid {
            return Err(refusal);
        }
        let mut scene = self.scene;
        if let Some((ids, named)) = self.named
            && scene.impulses.as_ref() == Some(&ids)
        {
            scene.impulses = Some(named.resolve_in(&scene)?);
        }
        Ok(scene)
    }
}

/// The refusal of `value` for `key`, for `reason`.
fn bad_value(key: &str, value: &str, reason: String) -> ModelError {
    ModelError::BadValue { key: key.to_owned(), value: value.to_owned(), reason }
}

/// The reason a changed scene does not read, without the line `in `bodies.motion`` that the
/// reader adds: the key is named already, and that path leaves out the element's name.
fn reason_of(e: &toml::de::Error) -> String {
    let message = e.message().trim_end();
    match message.rsplit_once('\n') {
        Some((reason, last)) if last.starts_with("in `") && last.ends_with('`') => {
            reason.trim_end().to_owned()
        }
        _ => message.to_owned(),
    }
}

/// Calls `f` with the dotted path of every value under `value` that is neither a table nor
/// an array of tables; the elements of an array of tables are named by their `name` field,
/// or by their index when they have none.
fn collect_leaves(value: &toml::Value, prefix: &str, f: &mut dyn FnMut(&str)) {
    let join = |k: &str| if prefix.is_empty() { k.to_owned() } else { format!("{prefix}.{k}") };
    match value {
        toml::Value::Table(table) => {
            for (k, v) in table {
                collect_leaves(v, &join(k), f);
            }
        }
        toml::Value::Array(items) if !items.is_empty() && items.iter().all(|v| v.is_table()) => {
            for (i, item) in items.iter().enumerate() {
                let name = item.get("name").and_then(toml::Value::as_str);
                collect_leaves(item, &join(&name.map_or_else(|| i.to_string(), str::to_owned)), f);
            }
        }
        _ => f(prefix),
    }
}

/// The value at a dotted path: table keys, and for arrays an index or (arrays of tables) the
/// `name` of an element.
fn leaf_mut<'a>(doc: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    let parts: Vec<&str> = if path.is_empty() { Vec::new() } else { path.split('.').collect() };
    tree::node_mut(doc, &parts)
}

/// Whether `first`, the first part of a key of a report model's scene, names one of the
/// scene's own entries (`dt`, `stop_at`, ...), present or left out, rather than one of the
/// model's parameters.
fn is_scene_key(doc: &toml::Value, first: &str) -> bool {
    first != "params"
        && (doc.get(first).is_some()
            || tree::fields_at(doc, &[]).is_some_and(|fields| fields.contains(&first)))
}

/// `path` with each index into an array of tables replaced by the `name` of its element,
/// where it has one (`bodies.1.mass` → `bodies.sleeve.mass`); the path as given elsewhere.
fn named_path(doc: &toml::Value, path: &str) -> String {
    let mut out = Vec::new();
    let mut at = Some(doc);
    for k in path.split('.') {
        let element = match at {
            Some(toml::Value::Array(items)) => k.parse::<usize>().ok().and_then(|i| items.get(i)),
            _ => None,
        };
        let name = element.and_then(|e| e.get("name")).and_then(toml::Value::as_str);
        out.push(name.unwrap_or(k));
        at = match (at, element) {
            (_, Some(e)) => Some(e),
            (Some(toml::Value::Table(t)), None) => t.get(k),
            (Some(toml::Value::Array(items)), None) => {
                items.iter().find(|e| e.get("name").and_then(toml::Value::as_str) == Some(k))
            }
            _ => None,
        };
    }
    out.join(".")
}

/// Parses a value given for a key the scene does not write (an optional field at its
/// default): a TOML value (`2`, `[0, 1]`, `true`, `{ kind = "linear", ... }`), or else the text
/// as a string.
fn parse_any(text: &str) -> toml::Value {
    let text = text.trim();
    toml::from_str::<toml::Table>(&format!("v = {text}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_owned()))
}

/// Parses `text` as a value of the same TOML type as `like`.
fn parse_like(like: &toml::Value, text: &str) -> Result<toml::Value, String> {
    let text = text.trim();
    match like {
        toml::Value::Float(_) | toml::Value::Integer(_)
            if matches!(like, toml::Value::Float(_)) =>
        {
            text.parse::<f64>().map(toml::Value::Float).or_else(|_| match parse_any(text) {
                // A table where a field takes a number or a table (a load, constant or a
                // sine); the scene's typed reading decides.
                table @ toml::Value::Table(_) => Ok(table),
                _ => Err(format!("expected a number, got `{text}`")),
            })
        }
        toml::Value::Integer(_) => text
            .parse::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| format!("expected a whole number, got `{text}`")),
        toml::Value::Boolean(_) => text
            .parse::<bool>()
            .map(toml::Value::Boolean)
            .map_err(|_| format!("expected true or false, got `{text}`")),
        toml::Value::String(_) => Ok(toml::Value::String(text.to_owned())),
        toml::Value::Array(_) | toml::Value::Table(_) => match parse_any(text) {
            // A number where a field takes a table or a number (a load given as a sine, set
            // to a constant); the scene's typed reading decides.
            value @ (toml::Value::Array(_)
            | toml::Value::Table(_)
            | toml::Value::Float(_)
            | toml::Value::Integer(_)) => Ok(value),
            _ if like.is_array() => {
                Err(format!("expected an array such as [0.0, 1.0], got `{text}`"))
            }
            _ => Err(format!("expected a table such as {{ key = 1.0 }}, got `{text}`")),
        },
        other => Err(format!("cannot set a value of type {}", other.type_str())),
    }
}
