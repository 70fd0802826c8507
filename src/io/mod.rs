//! Files in and out: extended XYZ snapshots, and scene files (with the `scene-file` feature).
