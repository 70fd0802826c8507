//! What a query file holds: the input columns of each layout, a chunk of rows read from any
//! format, and the result columns written back (docs/query-format.md).

use std::fmt;

use spheresweep::ShapeKind;

/// What the rows of an input file are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// Each row two spheres, A and B: the time they first touch.
    Pairs,
    /// Each row one sphere, queried against the static shapes of `--against`.
    Spheres,
}

/// The columns of a pairs file, in order: sphere A, then sphere B.
pub const PAIR_COLUMNS: [&str; 14] = [
    "ax", "ay", "az", "avx", "avy", "avz", "ar", "bx", "by", "bz", "bvx", "bvy", "bvz", "br",
];

/// The columns of a spheres file, in order.
pub const SPHERE_COLUMNS: [&str; 7] = ["x", "y", "z", "vx", "vy", "vz", "r"];

impl Layout {
    /// The input columns, in the order of a 2-D array's columns.
    pub fn columns(self) -> &'static [&'static str] {
        match self {
            Layout::Pairs => &PAIR_COLUMNS,
            Layout::Spheres => &SPHERE_COLUMNS,
        }
    }

    /// What one row is, for counts: `pairs`, `spheres`.
    pub fn rows_noun(self) -> &'static str {
        match self {
            Layout::Pairs => "pairs",
            Layout::Spheres => "spheres",
        }
    }

    /// The file kind in messages: `a pairs file`, `a spheres file`.
    pub fn file_noun(self) -> &'static str {
        match self {
            Layout::Pairs => "a pairs file",
            Layout::Spheres => "a spheres file (the input of --against)",
        }
    }

    /// The columns as a list for messages: `ax, ay, …, br`.
    pub fn column_list(self) -> String {
        self.columns().join(", ")
    }

    /// The other layout: the one the other mode of the query (with or without `--against`)
    /// reads.
    pub fn other(self) -> Layout {
        match self {
            Layout::Pairs => Layout::Spheres,
            Layout::Spheres => Layout::Pairs,
        }
    }

    /// For a message refusing an input that lacks this layout's columns: when it has every
    /// column of the other layout (`has` tells which names it has), the way to query it,
    /// as `; …` to end the message with; else nothing.
    pub fn other_layout_hint(self, has: impl Fn(&str) -> bool) -> &'static str {
        if self.other().columns().iter().all(|c| has(c)) {
            self.other_layout_text()
        } else {
            ""
        }
    }

    /// The same for an input whose shape is the other layout's (a 2-D array of `columns`
    /// columns).
    pub fn other_shape_hint(self, columns: u64) -> &'static str {
        if columns == self.other().columns().len() as u64 {
            self.other_layout_text()
        } else {
            ""
        }
    }

    fn other_layout_text(self) -> &'static str {
        match self {
            Layout::Pairs => {
                "; these are a spheres file's columns: to query every sphere against static \
                 shapes, give the shapes with --against SHAPES (a TOML or JSON file of [[plane]], \
                 [[cylinder]] and [[container]] tables, as in a scene file; docs/query-format.md)"
            }
            Layout::Spheres => {
                "; these are a pairs file's columns: a pairs file is queried without --against"
            }
        }
    }
}

/// Rows read from an input, one `f32` column per input column in the layout's order.
#[derive(Debug, Default)]
pub struct Chunk {
    /// Index of the first row in the whole input (rows counted from 0).
    pub first_row: u64,
    /// One column per input column of the layout, all of one length.
    pub columns: Vec<Vec<f32>>,
    /// The line of each row in a text input (CSV), for messages.
    pub lines: Option<Vec<u64>>,
}

impl Chunk {
    /// An empty chunk with `n` columns.
    pub fn new(n: usize) -> Self {
        Self {
            first_row: 0,
            columns: vec![Vec::new(); n],
            lines: None,
        }
    }

    /// Rows held.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// Empties the chunk for the rows from `first_row` on.
    pub fn clear(&mut self, first_row: u64) {
        self.first_row = first_row;
        self.columns.iter_mut().for_each(Vec::clear);
        if let Some(lines) = &mut self.lines {
            lines.clear();
        }
    }

    /// Where row `i` of the chunk is, for messages: `row 12 (line 14)`.
    pub fn locate(&self, i: usize) -> Place {
        Place {
            row: self.first_row + i as u64,
            line: self.lines.as_ref().and_then(|l| l.get(i).copied()),
        }
    }
}

/// A row of the input, counted from 0, and its line in a text file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Place {
    /// Row index in the whole input.
    pub row: u64,
    /// Line in the file (CSV only; the header is line 1).
    pub line: Option<u64>,
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line} (row {})", self.row),
            None => write!(f, "row {}", self.row),
        }
    }
}

/// A column of the results.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutColumn {
    /// Time of impact (f32; +inf: no contact in the window).
    Time,
    /// Kind of shape touched (spheres against shapes): 1 plane, 2 cylinder, 3 container, 255 none.
    Kind,
    /// Index of the shape touched among those of its kind (-1: none).
    Index,
    /// Contact point and normal (f64; NaN without a contact).
    Px,
    /// Contact point y.
    Py,
    /// Contact point z.
    Pz,
    /// Normal x.
    Nx,
    /// Normal y.
    Ny,
    /// Normal z.
    Nz,
}

/// The type of a result column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutType {
    /// 32-bit float.
    F32,
    /// 64-bit float.
    F64,
    /// Unsigned byte.
    U8,
    /// Signed 64-bit integer.
    I64,
}

/// The geometry columns, in order.
pub const GEOMETRY: [OutColumn; 6] = [
    OutColumn::Px,
    OutColumn::Py,
    OutColumn::Pz,
    OutColumn::Nx,
    OutColumn::Ny,
    OutColumn::Nz,
];

impl OutColumn {
    /// Every result column a query can write, in order.
    pub const ALL: [OutColumn; 9] = [
        OutColumn::Time,
        OutColumn::Kind,
        OutColumn::Index,
        OutColumn::Px,
        OutColumn::Py,
        OutColumn::Pz,
        OutColumn::Nx,
        OutColumn::Ny,
        OutColumn::Nz,
    ];

    /// Its name in headers, schemas and file names.
    pub fn name(self) -> &'static str {
        match self {
            OutColumn::Time => "time",
            OutColumn::Kind => "kind",
            OutColumn::Index => "index",
            OutColumn::Px => "px",
            OutColumn::Py => "py",
            OutColumn::Pz => "pz",
            OutColumn::Nx => "nx",
            OutColumn::Ny => "ny",
            OutColumn::Nz => "nz",
        }
    }

    /// Its type in the binary formats.
    pub fn ty(self) -> OutType {
        match self {
            OutColumn::Time => OutType::F32,
            OutColumn::Kind => OutType::U8,
            OutColumn::Index => OutType::I64,
            _ => OutType::F64,
        }
    }

    /// The result columns of a query, in order.
    pub fn of(layout: Layout, geometry: bool) -> Vec<OutColumn> {
        let mut cols = vec![OutColumn::Time];
        if layout == Layout::Spheres {
            cols.extend([OutColumn::Kind, OutColumn::Index]);
        }
        if geometry {
            cols.extend(GEOMETRY);
        }
        cols
    }
}

/// The code of "no contact" in the `kind` column of the binary formats (the shapes have
/// the library's `ShapeKind::code`).
pub const KIND_NONE: u8 = ShapeKind::NONE_CODE;

/// What is wrong with an input value beyond `f32`'s range, in every format's messages.
pub fn beyond_f32(value: impl fmt::Display) -> String {
    format!("{value} is beyond the range of f32 (magnitudes up to 3.4e38)")
}

/// An `f64` input rounded to `f32`, or `None` when it is finite but beyond `f32`'s range
/// (rounding would make it infinite). NaN and infinities pass, for validation to name.
pub fn narrow(v: f64) -> Option<f32> {
    let x = v as f32;
    (x.is_finite() || !v.is_finite()).then_some(x)
}

/// The name of a `kind` code in CSV output.
pub fn kind_name(code: u8) -> &'static str {
    match ShapeKind::from_code(code) {
        Some(kind) => kind.name(),
        None => "none",
    }
}

/// The results of one chunk, one entry per row in every column the query writes.
#[derive(Debug, Default)]
pub struct Results {
    /// Time of impact (+inf: none).
    pub time: Vec<f32>,
    /// Kind code of the shape touched (spheres against shapes only).
    pub kind: Vec<u8>,
    /// Index of the shape touched among its kind, -1 for none (spheres against shapes only).
    pub index: Vec<i64>,
    /// `px, py, pz, nx, ny, nz` (with `--geometry` only; NaN without a contact).
    pub geometry: [Vec<f64>; 6],
}

/// One result column's values, borrowed.
#[derive(Debug, Clone, Copy)]
pub enum Values<'a> {
    /// A float column.
    F32(&'a [f32]),
    /// A double column.
    F64(&'a [f64]),
    /// A byte column.
    U8(&'a [u8]),
    /// An integer column.
    I64(&'a [i64]),
}

impl Results {
    /// Empties every column.
    pub fn clear(&mut self) {
        self.time.clear();
        self.kind.clear();
        self.index.clear();
        self.geometry.iter_mut().for_each(Vec::clear);
    }

    /// Rows held.
    pub fn rows(&self) -> usize {
        self.time.len()
    }

    /// The values of `column`.
    pub fn values(&self, column: OutColumn) -> Values<'_> {
        match column {
            OutColumn::Time => Values::F32(&self.time),
            OutColumn::Kind => Values::U8(&self.kind),
            OutColumn::Index => Values::I64(&self.index),
            g => {
                let k = GEOMETRY.iter().position(|&c| c == g).unwrap_or(0);
                Values::F64(&self.geometry[k])
            }
        }
    }
}
