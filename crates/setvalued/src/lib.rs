//! moreau-setvalued.
