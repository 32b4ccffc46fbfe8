//! The error type of this crate.

/// Errors of `moreau-lcp`: invalid input data, invalid options, unreadable files.
///
/// A solver that runs but does not find a solution does **not** return an error: it
/// returns a [`Solution`](crate::Solution) whose [`Status`](crate::Status) says why.
/// Errors are reserved for input that no solver can accept.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum LcpError {
    /// The matrix M is not square.
    #[error("the LCP matrix M must be square, got {rows} x {cols}")]
    NotSquare {
        /// Number of rows of M.
        rows: usize,
        /// Number of columns of M.
        cols: usize,
    },
    /// A row of M given row by row has a length other than the number of rows.
    #[error("row {row} of the LCP matrix M has {found} entries, expected {expected} (one per row)")]
    RaggedRow {
        /// Index (0-based) of the first row of the wrong length.
        row: usize,
        /// The number of rows, which every row's length must equal.
        expected: usize,
        /// The row's length.
        found: usize,
    },
    /// Two sizes that must agree do not.
    #[error("dimension mismatch for {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// What was measured (for example `"q"` or `"covering vector d"`).
        what: &'static str,
        /// The size implied by M.
        expected: usize,
        /// The size given.
        found: usize,
    },
    /// An entry is NaN or infinite.
    #[error("non-finite entry in {what} at index {index:?}")]
    NonFinite {
        /// Which input (`"M"`, `"q"`, `"warm start"`, ...).
        what: &'static str,
        /// `(row, column)` of the entry; for vectors the column is 0.
        index: (usize, usize),
    },
    /// An entry is beyond the range the solvers compute in ([`MAX_ENTRY`](crate::MAX_ENTRY),
    /// 2^500 ≈ 3.3e150, in magnitude): products of such entries overflow. The LCP's M and q
    /// and the frictional-contact problem's W, q and μ are checked alike.
    #[error(
        "entry {what}[{}][{}] = {value:e} is beyond the range the solvers compute in \
         (|x| <= 2^500 = 3.3e150, so that products of entries stay finite); scale the \
         problem first: a row of (M, q) times a positive factor keeps z, a column j of M \
         times c_j > 0 maps z_j to z_j / c_j, and W and q of a frictional-contact problem \
         times one positive factor keep r",
        index.0,
        index.1
    )]
    OutOfRange {
        /// Which input (`"M"` or `"q"` of an LCP; `"W"`, `"q"` or `"μ"` of a
        /// frictional-contact problem, `"M"`, `"H"`, `"q"`, `"b"` or `"μ"` of a global one).
        what: &'static str,
        /// `(row, column)` of the entry; for vectors the column is 0.
        index: (usize, usize),
        /// Its value.
        value: f64,
    },
    /// A complementary basis gave a z or a w = M z + q beyond f64's range, so the answer
    /// asked for (every solution) cannot be given: a solution may exist that no f64 vector
    /// represents.
    #[error(
        "a basis gave z or w = M z + q beyond the range of f64 (1.8e308), so solutions may be \
         missed; scale the problem (rows of (M, q), or columns of M, by positive factors)"
    )]
    Overflow,
    /// The problem has size n = 0.
    #[error("the LCP is empty (n = 0)")]
    Empty,
    /// A solver option is out of its valid range.
    #[error("invalid option {name}: {reason}")]
    InvalidOption {
        /// Name of the option field.
        name: &'static str,
        /// Why the value was rejected.
        reason: String,
    },
    /// A text file could not be parsed.
    #[error("parse error on line {line}: {message}")]
    Parse {
        /// 1-based line number where the problem was found (0 if at end of input).
        line: usize,
        /// What went wrong.
        message: String,
    },
    /// Data after the last value of a problem in a text file: the sizes the file announces end
    /// the problem before them (a size too small, or two problems in one file).
    #[error(
        "unexpected data '{found}' on line {line} after {after}, where the problem ends by the \
         sizes the file announces"
    )]
    TrailingData {
        /// 1-based line number of the first unexpected token.
        line: usize,
        /// That token.
        found: String,
        /// The problem's last part (`q`, `μ`).
        after: &'static str,
    },
    /// A Siconos file names a matrix storage that does not exist.
    #[error(
        "unknown Siconos matrix storage type {storage} (0 = dense, 1 = sparse block, 2 = sparse)"
    )]
    UnsupportedStorage {
        /// The storage type number read from the file.
        storage: i64,
    },
    /// A text file is in neither of the formats that [`Lcp::read_any`](crate::Lcp::read_any)
    /// accepts; both reasons are kept.
    #[error("not a plain LCP file ({plain}) and not a Siconos LCP file ({siconos})")]
    UnknownFormat {
        /// Why the plain format did not parse.
        plain: Box<LcpError>,
        /// Why the Siconos format did not parse.
        siconos: Box<LcpError>,
    },
    /// A friction coefficient is negative.
    #[error("friction coefficient μ of contact {contact} is {mu}, it must be >= 0")]
    NegativeFriction {
        /// Index of the contact.
        contact: usize,
        /// Its μ.
        mu: f64,
    },
    /// The diagonal block of a contact (or of a group of bilateral rows) in W is not
    /// symmetric positive semidefinite, so its local problem is not a friction problem.
    #[error("diagonal block of {what} {index} is not symmetric positive semidefinite: {reason}")]
    NotPositiveSemidefinite {
        /// `"contact"` or `"bilateral group"`.
        what: &'static str,
        /// Index of the contact or of the bilateral group.
        index: usize,
        /// Which test failed, with the numbers.
        reason: String,
    },
    /// The sparsity structure of a block matrix is inconsistent (row pointers, column
    /// indices, missing diagonal block).
    #[error("invalid block structure: {0}")]
    Structure(String),
    /// The problem is larger than a size guard allows.
    #[error("problem size n = {n} exceeds the limit {max} of this solver")]
    TooLarge {
        /// Size of the problem.
        n: usize,
        /// Largest size accepted.
        max: usize,
    },
    /// The warm start vector has the wrong length.
    #[error("warm start has length {found}, expected {expected}")]
    WarmStartLength {
        /// n.
        expected: usize,
        /// Length given.
        found: usize,
    },
    /// Projected Gauss-Seidel needs every diagonal entry M_ii > 0.
    ///
    /// The PGS update `z_i <- max(0, z_i - ω (M z + q)_i / M_ii)` divides by M_ii; when
    /// M_ii <= 0 the one-dimensional subproblem in z_i is unbounded or has no unique
    /// minimiser, so the method is not defined. Use Lemke's method instead.
    #[error("projected Gauss-Seidel needs M_ii > 0, but M[{index}][{index}] = {value}")]
    NonPositiveDiagonal {
        /// Row (and column) of the offending diagonal entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A matrix that must be factored is singular.
    #[error("the matrix {what} is singular")]
    Singular {
        /// Which matrix.
        what: &'static str,
    },
    /// Reading or writing a file failed.
    #[error("i/o error: {0}")]
    Io(#[from] std::io::Error),
}

/// The rules shared by the solvers' options, each written once: every solver's options
/// `validate` with them, and the error names the field.
pub(crate) mod rules {
    use super::LcpError;

    /// [`LcpError::InvalidOption`] for field `name` with `reason`.
    pub(crate) fn invalid(name: &'static str, reason: &str) -> LcpError {
        LcpError::InvalidOption { name, reason: reason.to_string() }
    }

    /// A tolerance: finite and > 0.
    pub(crate) fn tolerance(value: f64) -> Result<(), LcpError> {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(invalid("tolerance", "must be finite and > 0"))
        }
    }

    /// A tolerance on the shared LCP residual's relative measure: in (0, 1), since z = 0
    /// (w = q) measures at most 1 whatever the problem, so 1 or more would accept it for an
    /// LCP that has no solution.
    pub(crate) fn relative_tolerance(value: f64) -> Result<(), LcpError> {
        if value > 0.0 && value < 1.0 {
            Ok(())
        } else {
            Err(invalid("tolerance", "must be in (0, 1)"))
        }
    }

    /// A relaxation factor ω of Gauss-Seidel sweeps: in (0, 2).
    pub(crate) fn omega(value: f64) -> Result<(), LcpError> {
        if value > 0.0 && value < 2.0 { Ok(()) } else { Err(invalid("omega", "must be in (0, 2)")) }
    }

    /// A count of iterations, sweeps or contacts: at least 1.
    pub(crate) fn count(name: &'static str, value: usize) -> Result<(), LcpError> {
        if value >= 1 { Ok(()) } else { Err(invalid(name, "must be >= 1")) }
    }
}
