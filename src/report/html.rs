//! A Markdown report as one self-contained HTML page: no network, inline SVG figures,
//! print-friendly.
//!
//! The Markdown is rendered by pulldown-cmark (CommonMark with tables). An image whose
//! target is a file of the output folder (`![…](charts.png)`) is replaced by that figure's
//! SVG inline when the folder holds `charts.svg`, otherwise by the PNG as a `data:` URI; an
//! image that is neither stays a plain link text. The page carries a Content Security
//! Policy that forbids every network load (`default-src 'none'`), so a browser opening it
//! offline shows exactly what it shows online.
//!
//! Everything of the Markdown is text: raw HTML in it (a block or inline tags, e.g. from a
//! problem's title) is shown as the characters it is, never as markup; a link goes only
//! where a link may (no `javascript:` or other scheme than http, https and mailto); a
//! control character (an escape, say) shows as `\u{1b}`. Only the figures are markup,
//! and they are built here.

use pulldown_cmark::{html, CowStr, Event, Options, Parser, Tag, TagEnd};

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
    // Whether each open link is kept (a link to an unsafe place keeps its text only).
    let mut links = Vec::new();
    let mut parser = Parser::new_ext(markdown, Options::ENABLE_TABLES).peekable();
    while let Some(event) = parser.next() {
        match event {
            Event::Start(Tag::Image { dest_url, title: caption, .. }) => {
                // The image's alt text is the events up to its end.
                let mut alt = String::new();
                for e in parser.by_ref() {
                    match e {
                        Event::End(TagEnd::Image) => break,
                        Event::Text(t) | Event::Code(t) | Event::Html(t) | Event::InlineHtml(t) => alt.push_str(&t),
                        _ => {}
                    }
                }
                let caption = if caption.is_empty() { alt.clone() } else { caption.to_string() };
                events.push(Event::Html(figure(&dest_url, &alt, &caption, figures).into()));
            }
            // Raw HTML of the Markdown is text: a block of it a paragraph.
            Event::Html(t) | Event::InlineHtml(t) => events.push(Event::Text(shown(t))),
            Event::Start(Tag::HtmlBlock) => events.push(Event::Start(Tag::Paragraph)),
            Event::End(TagEnd::HtmlBlock) => events.push(Event::End(TagEnd::Paragraph)),
            Event::Text(t) => events.push(Event::Text(shown(t))),
            Event::Code(t) => events.push(Event::Code(shown(t))),
            Event::Start(Tag::Link { link_type, dest_url, title, id }) => {
                let keep = safe_link(&dest_url);
                links.push(keep);
                if keep {
                    events.push(Event::Start(Tag::Link { link_type, dest_url, title: shown(title), id }));
                }
            }
            Event::End(TagEnd::Link) => {
                if links.pop().unwrap_or(true) {
                    events.push(Event::End(TagEnd::Link));
                }
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
        escape(&visible(title))
    )
}

/// Whether a link may go to `url`: a relative reference (a file, `#anchor`) or an http,
/// https or mailto URL. Browsers drop tabs and line breaks inside a URL and spaces around
/// it, so the scheme is read without them.
fn safe_link(url: &str) -> bool {
    let bare: String = url.chars().filter(|c| !c.is_ascii_whitespace() && !c.is_control()).collect();
    let end = bare.find([':', '/', '?', '#']);
    match end {
        Some(i) if bare[i..].starts_with(':') => {
            let scheme = bare[..i].to_ascii_lowercase();
            matches!(scheme.as_str(), "http" | "https" | "mailto")
        }
        _ => true,
    }
}

/// [`visible`] of a parser's text, kept as it is when it has nothing to show.
fn shown(text: CowStr<'_>) -> CowStr<'_> {
    match visible(&text) {
        std::borrow::Cow::Borrowed(_) => text,
        std::borrow::Cow::Owned(s) => s.into(),
    }
}

/// `text` with each control character (C0, DEL, C1) but tab and line breaks shown as its
/// escape (`\u{1b}`): a page or a figure shows an escape sequence of its input as the
/// characters it is (XML, and so SVG, cannot hold most control characters at all).
pub fn visible(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(|c| c.is_control() && !matches!(c, '\t' | '\n' | '\r')) {
        return text.into();
    }
    text.chars()
        .map(|c| {
            if c.is_control() && !matches!(c, '\t' | '\n' | '\r') {
                c.escape_debug().to_string()
            } else {
                c.to_string()
            }
        })
        .collect::<String>()
        .into()
}

/// `text` as Markdown that shows it as it is, on one line: each character that could
/// start inline markup (`\\`, `` ` ``, `*`, `_` but inside a word, `[`, `]`, `<`, `>`, `&`,
/// `|`, `#`, `~`, `!`) escaped with a backslash, line breaks as spaces and other control characters as their
/// escapes (`\u{1b}`). For input that goes into a report's Markdown inside a line (a
/// heading, a table cell), e.g. a problem's title.
pub fn markdown_literal(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let word = |i: Option<usize>| i.and_then(|i| chars.get(i)).is_some_and(|c| c.is_alphanumeric());
    let mut s = String::with_capacity(text.len());
    for (i, &c) in chars.iter().enumerate() {
        match c {
            '\n' | '\r' | '\t' => s.push(' '),
            c if c.is_control() => s.extend(c.escape_debug()),
            // Inside a word (`phi_op`) an underscore is no emphasis.
            '_' if word(i.checked_sub(1)) && word(Some(i + 1)) => s.push(c),
            '\\' | '`' | '*' | '_' | '[' | ']' | '<' | '>' | '&' | '|' | '#' | '~' | '!' => {
                s.push('\\');
                s.push(c);
            }
            c => s.push(c),
        }
    }
    s
}

/// `text` as a Markdown code span on one line: fenced by one backtick more than its longest
/// run of them, padded with a space each side when it begins or ends with a backtick (or
/// with a space on both sides, which Markdown would strip), line breaks as spaces and
/// other control characters but tab as their escapes (`\u{1b}`).
pub fn markdown_code(text: &str) -> String {
    let mut one_line = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\n' | '\r' => one_line.push(' '),
            c if c.is_control() && c != '\t' => one_line.extend(c.escape_debug()),
            c => one_line.push(c),
        }
    }
    let longest = one_line.split(|c| c != '`').map(str::len).max().unwrap_or(0);
    let fence = "`".repeat(longest + 1);
    let pad = one_line.starts_with('`')
        || one_line.ends_with('`')
        || (one_line.len() > 1 && one_line.starts_with(' ') && one_line.ends_with(' '));
    let pad = if pad { " " } else { "" };
    format!("{fence}{pad}{one_line}{pad}{fence}")
}

/// One figure: the SVG inline (its XML prolog dropped), or the PNG as a data URI, or the
/// alt text when the figure is not in the folder.
fn figure(name: &str, alt: &str, caption: &str, figures: &dyn Figures) -> String {
    let inner = if let Some(svg) = figures.svg(name) {
        let start = svg.find("<svg").unwrap_or(0);
        format!("<div role=\"img\" aria-label=\"{}\">{}</div>", escape(&visible(alt)), &svg[start..])
    } else if let Some(png) = figures.png(name) {
        format!("<img alt=\"{}\" src=\"data:image/png;base64,{}\">", escape(&visible(alt)), base64(&png))
    } else {
        return format!("<em>[figure {} not available]</em>", escape(&visible(name)));
    };
    format!("<figure>{inner}<figcaption>{}</figcaption></figure>", escape(&visible(caption)))
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

    /// What the page's body shows as markup: its tags, the figures' aside.
    fn tags(p: &str) -> Vec<String> {
        let body = &p[p.find("<body>").unwrap() + "<body>".len()..];
        body.split('<').skip(1).map(|t| t.split(['>', ' ']).next().unwrap_or("").to_string()).collect()
    }

    #[test]
    fn raw_html_in_the_markdown_is_text() {
        let hostile = "</title><script>alert(1)</script><img src=x onerror=alert(2)><b>bold</b>\u{1b}[31m";
        let md = format!(
            "# Report: {hostile}\n\ninline <i>x</i> and <a href=\"javascript:alert(3)\">y</a>\n\n<div onclick=\"alert(4)\">\nblock\n</div>\n\n<!-- comment -->\n\n[link](javascript:alert(5)) [tab](java\tscript:alert(6)) [ok](https://example.org/) [rel](cases/a/b.md) [anchor](#x) <javascript:alert(7)>\n"
        );
        let p = page(hostile, &md, &Two);
        let allowed = ["h1", "/h1", "p", "/p", "a", "/a"];
        for t in tags(&p) {
            assert!(allowed.contains(&t.as_str()) || t == "/body" || t == "/html", "tag <{t}> in {p}");
        }
        assert!(!p.contains("<a href=\"java"), "{p}");
        assert!(
            p.contains("<a href=\"https://example.org/\">ok</a>") && p.contains("<a href=\"cases/a/b.md\">rel</a>"),
            "{p}"
        );
        assert!(p.contains("<a href=\"#x\">anchor</a>"), "{p}");
        assert!(p.contains("&lt;script&gt;alert(1)&lt;/script&gt;") && p.contains("&lt;b&gt;bold&lt;/b&gt;"), "{p}");
        assert!(p.contains("<title>&lt;/title&gt;&lt;script&gt;"), "{p}");
        assert!(!p.contains('\u{1b}') && p.contains("\\u{1b}[31m"), "{p}");
    }

    #[test]
    fn literal_markdown_shows_the_text_as_it_is() {
        let hostile = "*em* _u_ phi_op `c` [l](javascript:x) <b>b</b> & # | ~ ! \\ x\ny\u{1b}";
        let md = format!("# T: {}\n\nafter\n", markdown_literal(hostile));
        let p = page("t", &md, &Two);
        let h1 = &p[p.find("<h1>").unwrap()..p.find("</h1>").unwrap() + 5];
        assert_eq!(
            h1, "<h1>T: *em* _u_ phi_op `c` [l](javascript:x) &lt;b&gt;b&lt;/b&gt; &amp; # | ~ ! \\ x y\\u{1b}</h1>",
            "{p}"
        );
        for (text, span) in [("a`b", "``a`b``"), ("`x`", "`` `x` ``"), (" a ", "`  a  `"), ("p\nq", "`p q`")] {
            assert_eq!(markdown_code(text), span);
        }
        let p = page("t", &format!("{}\n", markdown_code("a``b<i>")), &Two);
        assert!(p.contains("<code>a``b&lt;i&gt;</code>"), "{p}");
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
