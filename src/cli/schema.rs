//! `rubsim schema`: the JSON Schema of the scene format (for editors: taplo, Even Better TOML)
//! and the key reference docs/SCENE.md generated from it.

use anyhow::{Context, Result};
use rubsim::scene::schema;
use std::path::Path;

/// Writes the JSON Schema to `out` and the Markdown key reference to `markdown`, each when
/// given; with neither, prints the schema on stdout.
pub fn schema(out: Option<&Path>, markdown: Option<&Path>) -> Result<()> {
    let json = schema::json_text();
    if let Some(md) = markdown {
        let text = schema::markdown(&schema::json_schema());
        std::fs::write(md, text)
            .with_context(|| format!("{}: cannot write the key reference", md.display()))?;
    }
    match out {
        Some(p) => std::fs::write(p, json)
            .with_context(|| format!("{}: cannot write the schema", p.display()))?,
        None if markdown.is_none() => print!("{json}"),
        None => {}
    }
    Ok(())
}
