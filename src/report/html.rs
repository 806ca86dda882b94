//! A Markdown report as one self-contained HTML page: no network, inline SVG figures,
//! print-friendly.
//!
//! The Markdown is rendered by pulldown-cmark (CommonMark with tables). An image whose
//! target is a file of the output folder (`![…](charts.png)`) is replaced by that figure's
//! SVG inline when the folder holds `charts.svg`, otherwise by the PNG as a `data:` URI; an
//! image that is neither stays a plain link text. The page carries a Content Security
//! Policy that forbids every network load (`default-src 'none'`), so a browser opening it
//! offline shows exactly what it shows online.

use pulldown_cmark::{html, Event, Options, Parser, Tag, TagEnd};

/// The figures a page may embed: the SVG text or the PNG bytes of a file named in the
/// Markdown, looked up by its name as written (e.g. `charts.png`).
pub trait Figures {
    /// The SVG text of the figure named `name` (its `.svg` sibling), if there is one.
    fn svg(&self, name: &str) -> Option<String>;
    /// The PNG bytes of the figure named `name`, if there is one.
    fn png(&self, name: &str) -> Option<Vec<u8>>;
}

/// `name` if it is a plain file name of a folder (no path, no URL, not hidden), else
/// `None`: what a page may embed.
pub fn plain_name(name: &str) -> Option<&str> {
    let plain = !name.is_empty() && !name.contains(['/', '\\', ':']) && !name.starts_with('.');
    plain.then_some(name)
}

/// The style sheet: readable on screen, tables and figures kept whole when printed.
const STYLE: &str = "body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;max-width:60em;margin:2em auto;\
padding:0 1em;line-height:1.4;color:#222}table{border-collapse:collapse;margin:0.5em 0}\
th,td{border:1px solid #bbb;padding:0.2em 0.5em;text-align:left}th{background:#eee}\
figure{margin:1em 0}figure svg,figure img{max-width:100%;height:auto}code{background:#f4f4f4;padding:0 0.2em;overflow-wrap:anywhere}\
@media print{body{max-width:none;margin:0}figure,table{break-inside:avoid}h2{break-after:avoid}}";

/// The page of `markdown` titled `title`, with its figures embedded from `figures`.
pub fn page(title: &str, markdown: &str, figures: &dyn Figures) -> String {
    let mut events = Vec::new();
    let mut parser = Parser::new_ext(markdown, Options::ENABLE_TABLES).peekable();
    while let Some(event) = parser.next() {
        match event {
            Event::Start(Tag::Image { dest_url, title: caption, .. }) => {
                // The image's alt text is the events up to its end.
                let mut alt = String::new();
                for e in parser.by_ref() {
                    match e {
                        Event::End(TagEnd::Image) => break,
                        Event::Text(t) | Event::Code(t) => alt.push_str(&t),
                        _ => {}
                    }
                }
                let caption = if caption.is_empty() { alt.clone() } else { caption.to_string() };
                events.push(Event::Html(figure(&dest_url, &alt, &caption, figures).into()));
            }
            other => events.push(other),
        }
    }
    let mut body = String::new();
    html::push_html(&mut body, events.into_iter());
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data:; style-src 'unsafe-inline'\">\n\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        escape(title)
    )
}

/// One figure: the SVG inline (its XML prolog dropped), or the PNG as a data URI, or the
/// alt text when the figure is not in the folder.
fn figure(name: &str, alt: &str, caption: &str, figures: &dyn Figures) -> String {
    let inner = if let Some(svg) = figures.svg(name) {
        let start = svg.find("<svg").unwrap_or(0);
        format!("<div role=\"img\" aria-label=\"{}\">{}</div>", escape(alt), &svg[start..])
    } else if let Some(png) = figures.png(name) {
        format!("<img alt=\"{}\" src=\"data:image/png;base64,{}\">", escape(alt), base64(&png))
    } else {
        return format!("<em>[figure {} not available]</em>", escape(name));
    };
    format!("<figure>{inner}<figcaption>{}</figcaption></figure>", escape(caption))
}

/// Text safe inside HTML elements and attribute values.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Standard base64 (RFC 4648, with padding).
fn base64(bytes: &[u8]) -> String {
    use base64::Engine;
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Two;
    impl Figures for Two {
        fn svg(&self, name: &str) -> Option<String> {
            (name == "a.png").then(|| "<?xml version=\"1.0\"?>\n<svg width=\"10\" height=\"10\"></svg>".into())
        }
        fn png(&self, name: &str) -> Option<Vec<u8>> {
            (name == "b.png").then(|| b"Man".to_vec())
        }
    }

    #[test]
    fn figures_are_inlined_and_tables_rendered() {
        let md = "# R & D\n\n| a | b |\n|---|---|\n| 1 | 2 |\n\n![chart](a.png)\n\n![map](b.png)\n\n![gone](c.png)\n";
        let p = page("R & D", md, &Two);
        assert!(p.contains("<title>R &amp; D</title>"), "{p}");
        assert!(p.contains("<table>") && p.contains("<td>1</td>"), "{p}");
        assert!(p.contains("<svg width=\"10\" height=\"10\"></svg>") && !p.contains("<?xml"), "{p}");
        // "Man" is "TWFu" in base64 (RFC 4648, section 10).
        assert!(p.contains("src=\"data:image/png;base64,TWFu\""), "{p}");
        assert!(p.contains("[figure c.png not available]"), "{p}");
        assert!(!p.contains("src=\"c.png\"") && !p.contains("src=\"http"), "{p}");
    }

    #[test]
    fn base64_pads_like_rfc_4648() {
        // RFC 4648, section 10.
        for (i, o) in
            [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("fooba", "Zm9vYmE=")]
        {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn only_plain_names_of_the_folder_are_read() {
        for bad in ["../x.png", "/etc/x.png", "http://h/x.png", ".hidden.png", ""] {
            assert_eq!(plain_name(bad), None, "{bad}");
        }
        assert_eq!(plain_name("charts-1.png"), Some("charts-1.png"));
    }
}
