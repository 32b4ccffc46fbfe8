//! moreau-lcp.
