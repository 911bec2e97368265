//! The replay page: `page.html` with three.js, the viewer script and the frames filled in.
//!
//! three.js comes as ES modules (`three.core.js`, `three.module.js`, `OrbitControls.js`) that
//! import one another by name. The page keeps each as a JSON string in a
//! `<script type="application/json">` element (so no byte of it can end the element early), and
//! its loader turns them into `blob:` module URLs, pointing each import at the URL of the
//! module it names: everything is inline, nothing is fetched.

use super::json;
use super::three::ThreeJs;

/// The template; `{{NAME}}` marks where [`page`] puts each part.
const TEMPLATE: &str = include_str!("page.html");
/// The viewer (inline module code; see the file's header).
const VIEWER: &str = include_str!("viewer.js");

/// HTML text of `s` (for the title).
fn html_text(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The whole page: `title` (plain text), the replay data `data` (a JSON document, see
/// [`super::frames`]) and three.js. `Err` names a placeholder the template lacks or does not
/// know (a broken build, not a user error).
pub fn page(title: &str, data: &str, three: &ThreeJs) -> Result<String, String> {
    let quoted = |s: &str| {
        let mut out = String::new();
        json::string(&mut out, s);
        out
    };
    let parts: [(&str, String); 7] = [
        ("TITLE", html_text(title)),
        ("THREE_VERSION", html_text(&three.version)),
        ("THREE_CORE", quoted(&three.core)),
        ("THREE_MODULE", quoted(&three.module)),
        ("ORBIT_CONTROLS", quoted(&three.orbit_controls)),
        // the data's strings are written by json::string, which escapes `<`
        ("DATA", data.to_string()),
        ("VIEWER", VIEWER.to_string()),
    ];
    let size = TEMPLATE.len() + parts.iter().map(|(_, v)| v.len()).sum::<usize>();
    let mut out = String::with_capacity(size);
    let mut rest = TEMPLATE;
    let mut used = [false; 7];
    while let Some(open) = rest.find("{{") {
        out.push_str(&rest[..open]);
        let after = &rest[open + 2..];
        let close = after
            .find("}}")
            .ok_or("replay template: `{{` without `}}`")?;
        let name = &after[..close];
        let k = parts
            .iter()
            .position(|(n, _)| *n == name)
            .ok_or_else(|| format!("replay template: unknown placeholder {{{{{name}}}}}"))?;
        out.push_str(&parts[k].1);
        used[k] = true;
        rest = &after[close + 2..];
    }
    out.push_str(rest);
    if let Some(k) = used.iter().position(|u| !u) {
        return Err(format!(
            "replay template: no placeholder {{{{{}}}}}",
            parts[k].0
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inline_scripts_cannot_end_early() {
        // the viewer goes into a module <script> as it is
        assert!(!VIEWER.to_ascii_lowercase().contains("</script"));
        assert!(
            !VIEWER.contains("{{"),
            "the viewer must not hold a placeholder"
        );
        let three = ThreeJs {
            version: "0.0.0".into(),
            core: "export const A = '</script>';".into(),
            module: "import { A } from './three.core.js'; export { A };".into(),
            orbit_controls: "import { A } from 'three';".into(),
        };
        let html = page("run <1>", "{\"frames\":[]}", &three).unwrap();
        assert_eq!(
            html.to_ascii_lowercase().matches("</script").count(),
            html.to_ascii_lowercase().matches("<script").count()
        );
        assert!(html.contains("<title>run &lt;1&gt;"));
        assert!(html.contains("{\"frames\":[]}"));
    }
}
