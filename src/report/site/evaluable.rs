//! Which stored forms the page evaluates itself: the ones whose reconstruction it implements in
//! closed form, named by the stored form's `basis` (the sentence `Fitted::stored` declares),
//! never by an encoder's id. Every other encoding ships its values on the grid.

use crate::encoders::stored::{Stored, SH_IRRADIANCE};

/// How the page gets an encoding's E/π.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PageForm {
    /// E/π(n) = Σ c_i Y_i(n) over the stored entries `L{l}_{m}` (FORMULAS §2–3, bands 0–4),
    /// evaluated in the page (shader and script).
    ShIrradiance,
    /// The library's values on the site's grid, interpolated between nodes for the picture.
    Grid,
}

impl PageForm {
    /// The name the page's data carry: `sh` or `grid`.
    pub(super) fn name(self) -> &'static str {
        match self {
            PageForm::ShIrradiance => "sh",
            PageForm::Grid => "grid",
        }
    }
}

/// The page form of a stored form: [`PageForm::ShIrradiance`] when its basis is the SH
/// irradiance sentence and every entry is an RGB coefficient `L{l}_{m}` of band ≤ 4.
pub(super) fn page_form(stored: &Stored) -> PageForm {
    let sh_entries = stored.entries.iter().enumerate().all(|(i, e)| {
        i < 25 && e.name == crate::encoders::stored::sh_name(i) && e.value.scalars() == 3 && e.value.kind() == "rgb"
    });
    if stored.basis == SH_IRRADIANCE && sh_entries && !stored.entries.is_empty() {
        PageForm::ShIrradiance
    } else {
        PageForm::Grid
    }
}
