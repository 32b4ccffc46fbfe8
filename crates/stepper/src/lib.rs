//! moreau-stepper.
