//! Single values of a scene by their dotted keys, as given on a command line by
//! `--set key=value`: the keys a scene accepts, the entries a key reaches and the change of
//! one value, with the scene validated again.

use moreau_stepper::UnknownSolver;

use super::Scene;
use crate::{ModelError, ModelKind};

impl Scene {
    /// The keys the scene writes, which [`Self::set`] accepts: the scene's keys (`dt`,
    /// `t_end`, `record_every`, `solver`, ...) and then the model's parameters without the
    /// `params.` prefix (`m`, `eps_n`, `init.y0`, `beak.mu`, ...), or a declared mechanism's
    /// (`bodies.<name>.velocity`, `joints.<name>.anchor_a`, `contacts.<name>.mu`, ...; an
    /// array's entry as `bodies.<name>.velocity.0`).
    /// [`Self::set`] also takes, in a declared scene, the optional fields that its tables
    /// leave out (`bodies.<name>.density`, `projection`).
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

    /// The full dotted paths of the entries that [`Self::set`] with `key` changes: `solver`
    /// for `solver`, `params.init.y0` for `init.y0` or `y0`, and on the woodpecker
    /// `params.beak.mu`, `params.lower.mu` and `params.upper.mu` for `mu`. Two keys set the
    /// same entry exactly when their targets share a path.
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] listing the accepted keys.
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
        // A path into an array (`bodies.block.position.1`) or to an optional field that the
        // scene leaves at its default (`bodies.block.angle`) is not among the leaves; it is
        // accepted when everything up to its last part exists.
        // An element of an array of tables given by its index (`bodies.1.mass`) is named by
        // its `name`, as the leaves name it, so that two keys for one entry are seen as such.
        if self.kind() == ModelKind::Declared
            && let Ok(mut doc) = toml::Value::try_from(self)
            && let (parent, last) = key.rsplit_once('.').unwrap_or(("", key))
            && let Some(container) = leaf_mut(&mut doc, parent)
            && (container.is_table() || (container.is_array() && last.parse::<usize>().is_ok()))
        {
            let named = named_path(&doc, key);
            return Ok(match leaves.iter().find(|(_, full)| *full == named) {
                Some((_, full)) => vec![full.clone()],
                None => vec![named],
            });
        }
        Err(ModelError::UnknownKey {
            key: key.to_owned(),
            accepted: self.keys(),
            declared: self.kind() == ModelKind::Declared,
        })
    }

    /// Sets one value, as given on a command line by `--set key=value`.
    ///
    /// `key` is one of [`Self::keys`] (with or without the `params.` prefix) or a last part
    /// of one or more of them: `mu` on the woodpecker sets `beak.mu`, `lower.mu` and
    /// `upper.mu`; `v0` sets `init.v0`. `solver` takes a solver name (`auto`, `lemke`, `pgs`,
    /// `enum`). The value is parsed as the type the key already has (a number and a table
    /// stand for each other, as a load is either), and the whole scene is read and validated
    /// again; on any error the scene is left unchanged.
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] listing the accepted keys; [`ModelError::BadValue`] naming the
    /// key when the value does not parse or is out of range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), ModelError> {
        let bad = |reason: String| ModelError::BadValue {
            key: key.to_owned(),
            value: value.to_owned(),
            reason,
        };
        if key == "solver" {
            self.solver = value.trim().parse().map_err(|e: UnknownSolver| bad(e.to_string()))?;
            return Ok(());
        }
        let targets = self.targets(key)?;
        let mut doc = toml::Value::try_from(&*self).map_err(|e| bad(e.to_string()))?;
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
        let scene: Scene =
            doc.try_into().map_err(|e: toml::de::Error| bad(e.message().to_owned()))?;
        // A refusal that already names a key and its value is given as it is.
        scene.validate().map_err(|e| match e {
            ModelError::BadValue { .. } => e,
            other => bad(other.to_string()),
        })?;
        *self = scene;
        Ok(())
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
    if path.is_empty() {
        return Some(doc);
    }
    path.split('.').try_fold(doc, |v, k| match v {
        toml::Value::Table(t) => t.get_mut(k),
        toml::Value::Array(items) => match k.parse::<usize>() {
            Ok(i) => items.get_mut(i),
            Err(_) => items.iter_mut().find(|e| e.get("name").and_then(|n| n.as_str()) == Some(k)),
        },
        _ => None,
    })
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
