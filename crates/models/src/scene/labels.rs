//! The names under which a scene file writes a declared mechanism's impulses, so that a scene
//! edited between a run and its continuation still starts each contact and joint row from its
//! own impulses.
//!
//! In memory a contact is known by its identity (`StepReport::contact_ids`): on the detected
//! contact set two colliders' places in the list of every body's shapes and a feature of their
//! narrow phase, on the fixed one the slot's place in the contact list. Places change when a
//! body comes or goes before others, so the file names them instead:
//!
//! * a detected contact `"<body>.<shape>/<body>.<shape>/<feature>"`, e.g. `"grain12.0/floor.0/1"`
//!   (shape indices within each body, the colliders in the order of the bodies, the feature as
//!   the narrow phase numbers the pair's points);
//! * a slot of the fixed contact set by its name, as the record's columns do (`"hit"`);
//! * a joint row by its impulse's name (`"hinge.Lx"`, [`Multibody::bilateral_names`]).
//!
//! A body's name holds no `.`, so the first `.` of a detected contact's name ends its first
//! body's name and the one after the first `/` its second's.

use std::collections::HashMap;

use moreau_stepper::Impulses;
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::bodies::Multibody;
use crate::bodies::detect::{FEATURE_BITS, contact_id, split_id};

/// A contact of `[impulses]`: its name, or its identity (as a report model's contacts, and
/// as scene files written before names were, are given).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub(super) enum ContactKey {
    /// The contact's identity in the mechanism as the scene declares it.
    Id(u64),
    /// The contact's name (see the module's documentation).
    Name(String),
}

/// A joint row's impulse in `[impulses]`: a value for each row in order, or a row's name and
/// its value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub(super) enum JointEntry {
    /// The impulse of the row at this place.
    Value(f64),
    /// A row's name and its impulse.
    Named(String, f64),
}

/// The table `[impulses]` of a declared mechanism's scene file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileImpulses {
    /// `[contact, P_N, P_T]` per contact that carried an impulse (N s).
    #[serde(default)]
    pub contacts: Vec<(ContactKey, f64, f64)>,
    /// Λ_B of the joints' rows (N s, N m s).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointEntry>,
}

impl FileImpulses {
    /// The impulses by identity, as they are kept in memory.
    pub fn of_ids(impulses: &Impulses) -> Self {
        FileImpulses {
            contacts: impulses
                .contacts
                .iter()
                .map(|&(id, p_n, p_t)| (ContactKey::Id(id), p_n, p_t))
                .collect(),
            joints: impulses.joints.iter().map(|&l| JointEntry::Value(l)).collect(),
        }
    }

    /// Whether every entry is given by its place or identity, so that no mechanism is needed
    /// to read the table.
    fn is_numeric(&self) -> bool {
        self.contacts.iter().all(|(k, ..)| matches!(k, ContactKey::Id(_)))
            && self.joints.iter().all(|j| matches!(j, JointEntry::Value(_)))
    }

    /// [`Self::resolve`] by the names of the mechanism `scene` declares, built only when a
    /// name needs it.
    ///
    /// # Errors
    /// Those of [`Self::resolve`].
    pub fn resolve_in(self, scene: &super::Scene) -> Result<Impulses, ModelError> {
        self.resolve(|| match scene.build()? {
            crate::AnyModel::Declared(mb) => Ok(Some(mb)),
            _ => Ok(None),
        })
    }

    /// The impulses by identity: directly when every entry is numeric, otherwise by the names
    /// of `mechanism` (built from the scene on demand: `None` for a scene without names to
    /// resolve never builds it), sorted by identity as the stepper takes them.
    ///
    /// # Errors
    /// [`ModelError::BadValue`] (key `impulses.contacts.<k>` or `impulses.joints.<k>`) for a
    /// name the mechanism does not have, a contact named twice, named and numbered joint rows
    /// mixed; the errors of building the mechanism.
    pub fn resolve(
        self,
        mechanism: impl FnOnce() -> Result<Option<Multibody>, ModelError>,
    ) -> Result<Impulses, ModelError> {
        if self.is_numeric() {
            let contacts = self
                .contacts
                .into_iter()
                .map(|(k, p_n, p_t)| match k {
                    ContactKey::Id(id) => (id, p_n, p_t),
                    ContactKey::Name(_) => unreachable!("numeric"),
                })
                .collect();
            let joints =
                self.joints.iter().map(|j| if let JointEntry::Value(l) = j { *l } else { 0.0 });
            return Ok(Impulses { contacts, joints: joints.collect() });
        }
        let Some(mb) = mechanism()? else {
            return Err(bad(
                "impulses",
                "",
                "names contacts or joint rows, which only a declared mechanism has".to_owned(),
            ));
        };
        let labels = Labels::new(&mb);
        let mut contacts = Vec::with_capacity(self.contacts.len());
        for (k, (key, p_n, p_t)) in self.contacts.into_iter().enumerate() {
            let id = match key {
                ContactKey::Id(id) => id,
                ContactKey::Name(name) => labels
                    .contact(&name)
                    .map_err(|reason| bad(&format!("impulses.contacts.{k}"), &name, reason))?,
            };
            contacts.push((id, p_n, p_t));
        }
        contacts.sort_by_key(|c| c.0);
        if let Some(w) = contacts.windows(2).find(|w| w[0].0 == w[1].0) {
            let shown = labels.contact_name(w[0].0).unwrap_or_else(|| w[0].0.to_string());
            return Err(bad("impulses.contacts", &shown, "lists the contact twice".to_owned()));
        }
        let mut joints = vec![0.0; mb.rows.len()];
        for (k, entry) in self.joints.into_iter().enumerate() {
            let field = format!("impulses.joints.{k}");
            let JointEntry::Named(name, value) = entry else {
                let reason = "a value without its row's name, where other rows are named: name \
                              every row (`[\"<joint>.<row>\", Λ]`) or none"
                    .to_owned();
                return Err(bad(&field, "", reason));
            };
            let row = labels.row(&name).map_err(|reason| bad(&field, &name, reason))?;
            joints[row] = value;
        }
        Ok(Impulses { contacts, joints })
    }
}

/// The impulses of `mb` by name, for its scene file.
///
/// # Errors
/// [`ModelError::Unwritable`] for an identity that names no contact of the mechanism, or more
/// joint impulses than it has rows.
pub(super) fn named(mb: &Multibody, impulses: &Impulses) -> Result<FileImpulses, ModelError> {
    let labels = Labels::new(mb);
    let contacts = impulses
        .contacts
        .iter()
        .map(|&(id, p_n, p_t)| {
            let name = labels.contact_name(id).ok_or_else(|| ModelError::Unwritable {
                message: format!("impulses: contact identity {id} names no contact of the scene"),
            })?;
            Ok((ContactKey::Name(name), p_n, p_t))
        })
        .collect::<Result<_, ModelError>>()?;
    let rows = mb.bilateral_names();
    if impulses.joints.len() > rows.len() {
        return Err(ModelError::Unwritable {
            message: format!(
                "impulses: {} joint impulses for the mechanism's {} joint rows",
                impulses.joints.len(),
                rows.len()
            ),
        });
    }
    let joints = rows.into_iter().zip(&impulses.joints).map(|(n, &l)| JointEntry::Named(n, l));
    Ok(FileImpulses { contacts, joints: joints.collect() })
}

/// The names of a mechanism's contacts and joint rows, and their places.
struct Labels<'a> {
    mb: &'a Multibody,
    /// Per body, the index of its first collider.
    first_collider: Vec<usize>,
    /// Body index by name.
    bodies: HashMap<&'a str, usize>,
    /// Slot index by name (the fixed contact set).
    slots: HashMap<&'a str, usize>,
    /// Joint row index by name.
    rows: HashMap<String, usize>,
}

impl<'a> Labels<'a> {
    fn new(mb: &'a Multibody) -> Self {
        let mut first_collider = Vec::with_capacity(mb.bodies.len());
        let mut next = 0;
        for body in &mb.bodies {
            first_collider.push(next);
            next += body.shapes.len();
        }
        let bodies = mb.bodies.iter().enumerate().map(|(i, b)| (b.name.as_str(), i)).collect();
        let slots = mb.contact_names.iter().enumerate().map(|(i, n)| (n.as_str(), i)).collect();
        let rows = mb.bilateral_names().into_iter().enumerate().map(|(i, n)| (n, i)).collect();
        Labels { mb, first_collider, bodies, slots, rows }
    }

    /// The name of the contact of identity `id`, `None` when there is none such.
    fn contact_name(&self, id: u64) -> Option<String> {
        let Some(detector) = &self.mb.detector else {
            return self.mb.contact_names.get(usize::try_from(id).ok()?).cloned();
        };
        let (i, j, feature) = split_id(id);
        let name = |c: usize| {
            let &(b, s) = detector.colliders.get(c)?;
            Some(format!("{}.{s}", self.mb.bodies[b].name))
        };
        Some(format!("{}/{}/{feature}", name(i)?, name(j)?))
    }

    /// The identity of the contact named `name`, or why there is none.
    fn contact(&self, name: &str) -> Result<u64, String> {
        if self.mb.detector.is_none() {
            return match self.slots.get(name) {
                Some(&i) => Ok(i as u64),
                None => Err("names no contact of the scene's contact list".to_owned()),
            };
        }
        let form = || {
            "is not a detected contact's name `<body>.<shape>/<body>.<shape>/<feature>` (e.g. \
             `grain3.0/floor.0/1`)"
                .to_owned()
        };
        let (a, rest) = collider(name).ok_or_else(form)?;
        let rest = rest.strip_prefix('/').ok_or_else(form)?;
        let (b, rest) = collider(rest).ok_or_else(form)?;
        let feature: u32 = rest.strip_prefix('/').and_then(|f| f.parse().ok()).ok_or_else(form)?;
        let place = |(body, shape): (&str, usize)| -> Result<usize, String> {
            let &i = self
                .bodies
                .get(body)
                .ok_or_else(|| format!("names the body `{body}`, which the scene does not have"))?;
            let shapes = self.mb.bodies[i].shapes.len();
            if shape >= shapes {
                return Err(format!("names shape {shape} of `{body}`, which has {shapes}"));
            }
            Ok(self.first_collider[i] + shape)
        };
        let (i, j) = (place(a)?, place(b)?);
        if i >= j {
            return Err(format!(
                "names `{}` first, which the scene now declares after `{}` (or the same \
                 shape twice): the feature would name another point of the pair; declare the \
                 bodies in their former order, or delete the contact's line",
                a.0, b.0
            ));
        }
        if feature >= 1 << FEATURE_BITS {
            return Err(format!("feature {feature} is above the largest, 2^16 − 1"));
        }
        Ok(contact_id(i, j, feature))
    }

    /// The index of the joint row named `name`, or why there is none.
    fn row(&self, name: &str) -> Result<usize, String> {
        self.rows.get(name).copied().ok_or_else(|| {
            "names no row of the scene's joints (`<joint>.<row>` as the record's columns name \
             them, e.g. `hinge.Lx`)"
                .to_owned()
        })
    }
}

/// A collider's name `<body>.<shape>` at the start of `s`, and the rest of `s`.
fn collider(s: &str) -> Option<((&str, usize), &str)> {
    let (body, rest) = s.split_once('.')?;
    let digits = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
    let shape = rest[..digits].parse().ok()?;
    (!body.is_empty()).then_some(((body, shape), &rest[digits..]))
}

fn bad(key: &str, value: &str, reason: String) -> ModelError {
    ModelError::BadValue { key: key.to_owned(), value: value.to_owned(), reason }
}
