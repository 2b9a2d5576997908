//! Where an export's bytes go: to the path chosen, on the desktop; in a web page (no disk)
//! to the browser as a download named as the path's file.

use super::ExportError;
use crate::config::CaseFile;
use std::path::Path;

/// Writes `bytes` to `path`, or in a page, offers them as a download.
#[cfg(not(target_arch = "wasm32"))]
pub fn deliver(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    std::fs::write(path, bytes).map_err(ExportError::io(path))
}

/// Writes `bytes` to `path`, or in a page, offers them as a download.
#[cfg(target_arch = "wasm32")]
pub fn deliver(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    let name = path.file_name().map_or_else(|| "ringlab-export".into(), |n| n.to_string_lossy());
    download(&name, bytes).map_err(|e| {
        ExportError::Invalid(format!("{name}: the browser did not take the download: {e}"))
    })
}

/// A link to the bytes as a blob, clicked: the browser's own download, its folder the
/// browser's choice. The blob's URL stays valid for the page's life (a few exports a lesson).
#[cfg(target_arch = "wasm32")]
fn download(name: &str, bytes: &[u8]) -> Result<(), String> {
    use wasm_bindgen::JsCast;
    let js = |e: wasm_bindgen::JsValue| format!("{e:?}");
    let document = web_sys::window().and_then(|w| w.document()).ok_or("no document")?;
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    let blob = web_sys::Blob::new_with_u8_array_sequence(&parts).map_err(js)?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(js)?;
    let link = document
        .create_element("a")
        .map_err(js)?
        .dyn_into::<web_sys::HtmlAnchorElement>()
        .map_err(|_| "no link element")?;
    link.set_href(&url);
    link.set_download(name);
    link.click();
    Ok(())
}

/// File > Save case: a case that does not build is refused (the file would not open again).
pub fn save_case(path: &Path, file: &CaseFile) -> Result<(), String> {
    file.build()
        .map_err(|m| format!("{}: the case is not valid, not saved: {m}", path.display()))?;
    let text = file.to_toml().map_err(|m| format!("{}: {m}", path.display()))?;
    deliver(path, text.as_bytes()).map_err(|e| e.to_string())
}
