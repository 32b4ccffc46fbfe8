//! moreau-models.
