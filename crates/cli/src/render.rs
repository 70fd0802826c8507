//! `spheresweep render`: not written yet (issue 16); refuses to run rather than pretend.

use std::error::Error;

/// Options of `spheresweep render`.
#[derive(Debug, clap::Args)]
pub struct Args {}

pub fn run(_args: &Args) -> Result<(), Box<dyn Error>> {
    Err("spheresweep render is not implemented yet".into())
}
