//! The refusal of a `--set` key that names no entry of the scene: the level of the scene's
//! tree where the key leaves it, the keys of that level, and the nearest of them.
//!
//! The scene's own checks tell an unknown key in two ways: as an unknown key when the path
//! above its last part does not exist (`bodies.bal.mass`, `eps_nn` on a report model), and,
//! in a declared scene, whose tables also take the optional fields they leave out, as a bad
//! value when the table exists but has no such field (`zzz`, `bodies.ball.masss`: its reading
//! says `unknown field`). Both become [`CliError::UnknownKey`].

use moreau_models::{ModelError, ModelKind, Scene};

use crate::error::CliError;

/// The largest edit distance at which a key is suggested.
const NEAREST: usize = 2;

/// A field name no scene has, set to learn the fields of a table from its refusal.
const PROBE: &str = "?";

/// The refusal of `key`, which `error` (the scene's refusal of `--set key=...`) says is
/// unknown; `None` when `error` is about something else (a bad value, an unknown field of a
/// value given as a table).
pub(crate) fn unknown_key(scene: &Scene, key: &str, error: &ModelError) -> Option<CliError> {
    let short = key.strip_prefix("params.").unwrap_or(key);
    match error {
        ModelError::UnknownKey { .. } => {
            let parts: Vec<&str> = short.split('.').collect();
            let keys = scene.keys();
            // The deepest level of the scene's tree that the key reaches.
            let depth = (0..parts.len())
                .rev()
                .find(|&d| d == 0 || is_level(&keys, &parts[..d].join(".")))
                .unwrap_or(0);
            let level = parts[..depth].join(".");
            let valid = keys_of(scene, &keys, &level);
            Some(refusal(key, &level, parts[depth], &parts[depth + 1..], valid))
        }
        ModelError::BadValue { reason, .. } => {
            let (name, listed) = unknown_field(reason)?;
            let (level, last) = short.rsplit_once('.').unwrap_or(("", short));
            if name != last {
                return None;
            }
            let valid = listed.unwrap_or_else(|| keys_of(scene, &scene.keys(), level));
            Some(refusal(key, level, last, &[], valid))
        }
        _ => None,
    }
}

/// The refusal of `key`, whose part `name` is not among the keys `valid` of `level`; `rest`
/// are the parts after it.
fn refusal(key: &str, level: &str, name: &str, rest: &[&str], valid: Vec<String>) -> CliError {
    let suggestion = nearest(name, &valid).map(|near| {
        let mut parts: Vec<&str> = Vec::new();
        if !level.is_empty() {
            parts.push(level);
        }
        parts.push(near);
        parts.extend(rest);
        parts.join(".")
    });
    CliError::UnknownKey {
        key: key.to_owned(),
        level: level.to_owned(),
        name: name.to_owned(),
        valid,
        suggestion,
    }
}

/// The keys of `level` of `scene`, whose keys are `keys`: a declared table's fields (its
/// optional ones included), the names of a declared array's elements; a report model's keys
/// under the level, whole (`init.y0` at the top).
fn keys_of(scene: &Scene, keys: &[String], level: &str) -> Vec<String> {
    if scene.kind() == ModelKind::Declared {
        return fields_of(scene, level).unwrap_or_else(|| children(keys, level));
    }
    keys.iter()
        .filter_map(|k| match level {
            "" => Some(k.clone()),
            _ => k.strip_prefix(level).and_then(|r| r.strip_prefix('.')).map(str::to_owned),
        })
        .collect()
}

/// Whether some key of the scene lies under `level`.
fn is_level(keys: &[String], level: &str) -> bool {
    keys.iter().any(|k| k.strip_prefix(level).is_some_and(|rest| rest.starts_with('.')))
}

/// The next parts of the keys under `level` (all first parts for the top), in order, once.
fn children(keys: &[String], level: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for k in keys {
        let rest = if level.is_empty() {
            Some(k.as_str())
        } else {
            k.strip_prefix(level).and_then(|r| r.strip_prefix('.'))
        };
        if let Some(rest) = rest {
            let next = rest.split('.').next().unwrap_or(rest);
            if !out.iter().any(|o| o == next) {
                out.push(next.to_owned());
            }
        }
    }
    out
}

/// The fields of the table at `level` of a declared scene, those it leaves out included, as
/// its reading lists them when given a field it does not have.
fn fields_of(scene: &Scene, level: &str) -> Option<Vec<String>> {
    let probe = if level.is_empty() { PROBE.to_owned() } else { format!("{level}.{PROBE}") };
    match scene.clone().set(&probe, "0") {
        Err(ModelError::BadValue { reason, .. }) => match unknown_field(&reason)? {
            (PROBE, listed) => listed,
            _ => None,
        },
        _ => None,
    }
}

/// The field that a reading of the scene calls unknown, and the fields it lists instead
/// (`unknown field `x`, expected one of `a`, `b``, `... expected `a``, `... there are no
/// fields`; `None` for a list in another form).
fn unknown_field(reason: &str) -> Option<(&str, Option<Vec<String>>)> {
    let first = reason.lines().next()?;
    let (name, rest) = first.strip_prefix("unknown field `")?.split_once('`')?;
    let quoted = |list: &str| -> Option<Vec<String>> {
        list.split(", ")
            .map(|f| f.strip_prefix('`').and_then(|f| f.strip_suffix('`')).map(str::to_owned))
            .collect()
    };
    let listed = if let Some(list) = rest.strip_prefix(", expected one of ") {
        quoted(list)
    } else if let Some(one) = rest.strip_prefix(", expected ") {
        quoted(one)
    } else if rest.starts_with(", there are no fields") {
        Some(Vec::new())
    } else {
        None
    };
    Some((name, listed))
}

/// The key of `valid` nearest to `name`, when one alone lies within [`NEAREST`] edits of it
/// and nearer than its length.
fn nearest<'a>(name: &str, valid: &'a [String]) -> Option<&'a str> {
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

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn the_readings_refusal_of_an_unknown_field_is_understood() {
        let (name, listed) =
            unknown_field("unknown field `masss`, expected one of `name`, `mass`\nin `bodies`")
                .expect("an unknown field");
        assert_eq!((name, listed), ("masss", Some(vec!["name".to_owned(), "mass".to_owned()])));
        assert_eq!(
            unknown_field("unknown field `x`, expected `a`"),
            Some(("x", Some(vec!["a".to_owned()])))
        );
        assert_eq!(
            unknown_field("unknown field `x`, there are no fields"),
            Some(("x", Some(vec![])))
        );
        assert_eq!(unknown_field("expected a number, got `x`"), None);
    }
}
