//! A claim's figures (`figure`): the evidence of ours on its paper's page, for a claim whose
//! paper evidence is an image. Each is a committed `.png` under `results/` with a caption
//! saying what to look at; one that names a `sheet` is drawn by `probelab claims` itself (the
//! comparison sheet of one experiment on one map, cut down to the claim's encoders) as
//! `results/claims/<name>.png`, so the page shows what the claim is about rather than a whole
//! sheet.

use super::file::{FigureField, FigureFile};
use crate::math::echo::value as echo;
use anyhow::{bail, Result};

/// One figure beside a claim's paragraph.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Its path under `results/` (plain folder and file names, `.png`).
    pub image: String,
    /// What to look at.
    pub caption: String,
    /// The sheet `probelab claims` draws as `image`, if it draws one.
    pub sheet: Option<SheetCrop>,
}

/// A comparison sheet cut down to a claim: one experiment's representative case on one map,
/// with only the named encoders (in this order), drawn as the report draws every sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct SheetCrop {
    /// The experiment (`experiments/<experiment>.toml`).
    pub experiment: String,
    /// The map, one of the experiment's.
    pub map: String,
    /// The encoder names of the experiment to draw, in order.
    pub encoders: Vec<String>,
}

/// The figures of a claim's `figure` (one table or a list of them), each checked: a `.png`
/// under `results/` by plain names with a caption; a drawn sheet lives in `claims/` and names
/// an experiment, a map and at least one encoder.
pub(super) fn figures(field: Option<FigureField>) -> Result<Vec<Figure>> {
    let files = match field {
        None => vec![],
        Some(FigureField::One(f)) => vec![f],
        Some(FigureField::Many(v)) => v,
    };
    files.into_iter().map(figure).collect()
}

fn figure(f: FigureFile) -> Result<Figure> {
    let FigureFile { image, caption, sheet } = f;
    let plain = image.split('/').all(|p| crate::io::name::check(p).is_ok());
    if !plain || !image.ends_with(".png") || caption.trim().is_empty() {
        bail!("figure '{}': a .png under results/ named by plain folder and file names, with a caption", echo(&image));
    }
    let sheet = match sheet {
        None => None,
        Some(s) => {
            if !image.starts_with("claims/") || image.matches('/').count() != 1 {
                bail!("figure '{}': a drawn sheet is written as claims/<name>.png", echo(&image));
            }
            if s.encoders.is_empty() || s.experiment.trim().is_empty() || s.map.trim().is_empty() {
                bail!("figure '{}': its sheet names an experiment, a map and at least one encoder", echo(&image));
            }
            Some(SheetCrop { experiment: s.experiment, map: s.map, encoders: s.encoders })
        }
    };
    Ok(Figure { image, caption, sheet })
}

#[cfg(test)]
mod tests {
    use crate::claims::declaration::parse::parse;
    use std::path::Path;

    /// A claim whose `figure` is `fig` (TOML after `figure = `).
    fn claim(fig: &str) -> anyhow::Result<crate::claims::declaration::Paper> {
        let text = format!(
            "title='T'\nauthors='A'\nvenue='V'\norder=1\n[[claim]]\nid='X1'\nsays='s'\npaper_figure='p'\n\
             criterion='c'\nkind='measured'\nfixed='before data'\ndiffers='d'\nquote='q'\nthreshold_from='direction'\n\
             figure = {fig}\n[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\ntest='ratio_every'\n\
             role='primary'\n"
        );
        parse("t", &text, Path::new("t.toml"))
    }

    /// One figure or a list; a drawn sheet lives in claims/ and names what it draws.
    #[test]
    fn figures_are_one_or_a_list_and_sheets_are_checked() {
        let one = claim("{ image = 'x/a.png', caption = 'look' }").unwrap();
        assert_eq!(one.claims[0].figures.len(), 1);
        assert!(one.claims[0].figures[0].sheet.is_none());
        let sheet =
            "{ image = 'claims/s.png', caption = 'c', sheet = { experiment = 'e', map = 'm', encoders = ['a', 'b'] } }";
        let two = claim(&format!("[{{ image = 'x/a.png', caption = 'look' }}, {sheet}]")).unwrap();
        let figs = &two.claims[0].figures;
        assert_eq!(figs.len(), 2);
        let crop = figs[1].sheet.as_ref().unwrap();
        assert_eq!((crop.experiment.as_str(), crop.map.as_str(), crop.encoders.len()), ("e", "m", 2));
        let err = |f: &str| format!("{:#}", claim(f).unwrap_err());
        assert!(err("{ image = 'x/a.jpg', caption = 'c' }").contains("a .png under results/"));
        assert!(err("{ image = 'x/a.png', caption = ' ' }").contains("with a caption"));
        let outside = "{ image = 'x/s.png', caption = 'c', sheet = { experiment = 'e', map = 'm', encoders = ['a'] } }";
        assert!(err(outside).contains("claims/<name>.png"), "{}", err(outside));
        let empty = "{ image = 'claims/s.png', caption = 'c', sheet = { experiment = 'e', map = 'm', encoders = [] } }";
        assert!(err(empty).contains("at least one encoder"));
    }
}
