//! Driving the app in a real headless Chromium, as a person does: launching the browser on a server of
//! our own, mouse and key events, waiting for the page, screenshots. Each test file that uses it is
//! one browser session.
//!
//! Chromium is `/usr/bin/chromium` (or `$LINKWRIGHT_CHROMIUM`). Without it a test is skipped with a
//! message, except under `CI=true`, where a missing browser is a failure. With
//! `LINKWRIGHT_SCREENSHOTS=DIR` screenshots are written to DIR.
#![allow(dead_code, reason = "each test file uses a different part of this module")]

use crate::common::Server;
use chromiumoxide::browser::{Browser, BrowserConfig};
use chromiumoxide::cdp::browser_protocol::browser::{SetDownloadBehaviorBehavior, SetDownloadBehaviorParams};
use chromiumoxide::cdp::browser_protocol::dom::SetFileInputFilesParams;
use chromiumoxide::cdp::browser_protocol::emulation::SetDeviceMetricsOverrideParams;
use chromiumoxide::cdp::browser_protocol::input::{
    DispatchKeyEventParams, DispatchKeyEventType, DispatchMouseEventParams, DispatchMouseEventType, InsertTextParams,
    MouseButton,
};
use chromiumoxide::cdp::browser_protocol::page::CaptureScreenshotFormat;
use chromiumoxide::cdp::js_protocol::runtime::EventExceptionThrown;
use chromiumoxide::handler::viewport::Viewport;
use chromiumoxide::page::ScreenshotParams;
use chromiumoxide::Page;
use futures_util::StreamExt;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub(crate) type Result<T> = std::result::Result<T, Box<dyn std::error::Error + Send + Sync>>;

pub(crate) const WIDTH: u32 = 1400;
pub(crate) const HEIGHT: u32 = 860;

/// The browser to drive: `$LINKWRIGHT_CHROMIUM` or Debian's `/usr/bin/chromium`; `Err` names the path
/// that is missing.
pub(crate) fn chromium() -> std::result::Result<PathBuf, PathBuf> {
    let path =
        std::env::var_os("LINKWRIGHT_CHROMIUM").map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    if path.is_file() {
        Ok(path)
    } else {
        Err(path)
    }
}

pub(crate) fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkwright-e2e-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
}

/// Evaluates `js` in the page and returns its JSON value.
pub(crate) async fn eval(page: &Page, js: &str) -> Result<Value> {
    Ok(page.evaluate(js).await?.into_value::<Value>().unwrap_or(Value::Null))
}

/// Waits until the page has drawn its latest change (two animation frames).
pub(crate) async fn settle(page: &Page) -> Result<()> {
    eval(page, "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(true))))").await?;
    Ok(())
}

/// Waits until `js` evaluates to true.
pub(crate) async fn until(page: &Page, js: &str, within: Duration) -> Result<()> {
    let start = Instant::now();
    loop {
        if eval(page, js).await? == Value::Bool(true) {
            return Ok(());
        }
        if start.elapsed() > within {
            return Err(format!("timed out after {within:?} waiting for {js}").into());
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Clicks the element `selector` as soon as it is there. The click is dispatched in the page, because
/// panels are rebuilt on every change and a node found a moment earlier may be gone.
pub(crate) async fn click(page: &Page, selector: &str) -> Result<()> {
    let js = format!(
        "(() => {{ const e = document.querySelector({}); if (!e || e.disabled) return false; e.click(); return true; }})()",
        serde_json::to_string(selector)?
    );
    until(page, &js, Duration::from_secs(5)).await.map_err(|e| format!("click {selector}: {e}"))?;
    settle(page).await
}

pub(crate) async fn mouse(page: &Page, kind: DispatchMouseEventType, x: f64, y: f64, buttons: i64) -> Result<()> {
    clicked(page, kind, (x, y), buttons, 1).await
}

/// A mouse event at `p`, the `count`th click of a quick series (2: a double-click's second).
async fn clicked(page: &Page, kind: DispatchMouseEventType, p: (f64, f64), buttons: i64, count: i64) -> Result<()> {
    let mut event = DispatchMouseEventParams::builder().r#type(kind.clone()).x(p.0).y(p.1).buttons(buttons);
    if kind != DispatchMouseEventType::MouseMoved {
        event = event.button(MouseButton::Left).click_count(count);
    }
    page.execute(event.build()?).await?;
    Ok(())
}

/// Presses at `from`, moves in steps to `to`, releases: a drag with the left button.
pub(crate) async fn drag(page: &Page, from: (f64, f64), to: (f64, f64)) -> Result<()> {
    mouse(page, DispatchMouseEventType::MouseMoved, from.0, from.1, 0).await?;
    mouse(page, DispatchMouseEventType::MousePressed, from.0, from.1, 1).await?;
    for i in 1..=8 {
        let t = f64::from(i) / 8.0;
        mouse(page, DispatchMouseEventType::MouseMoved, from.0 + (to.0 - from.0) * t, from.1 + (to.1 - from.1) * t, 1)
            .await?;
    }
    mouse(page, DispatchMouseEventType::MouseReleased, to.0, to.1, 0).await?;
    settle(page).await
}

/// A click with the left button at a page position.
pub(crate) async fn tap(page: &Page, p: (f64, f64)) -> Result<()> {
    mouse(page, DispatchMouseEventType::MouseMoved, p.0, p.1, 0).await?;
    mouse(page, DispatchMouseEventType::MousePressed, p.0, p.1, 1).await?;
    mouse(page, DispatchMouseEventType::MouseReleased, p.0, p.1, 0).await?;
    settle(page).await
}

/// A double-click with the left button at a page position.
pub(crate) async fn double_tap(page: &Page, p: (f64, f64)) -> Result<()> {
    mouse(page, DispatchMouseEventType::MouseMoved, p.0, p.1, 0).await?;
    for count in [1, 2] {
        clicked(page, DispatchMouseEventType::MousePressed, p, 1, count).await?;
        clicked(page, DispatchMouseEventType::MouseReleased, p, 0, count).await?;
    }
    settle(page).await
}

/// A key press with modifiers (2 = Ctrl, 8 = Shift).
pub(crate) async fn key(page: &Page, key: &str, code: &str, key_code: i64, modifiers: i64) -> Result<()> {
    for kind in [DispatchKeyEventType::RawKeyDown, DispatchKeyEventType::KeyUp] {
        let event = DispatchKeyEventParams::builder()
            .r#type(kind)
            .key(key)
            .code(code)
            .windows_virtual_key_code(key_code)
            .modifiers(modifiers)
            .build()?;
        page.execute(event).await?;
    }
    Ok(())
}

/// A key pressed as a keyboard does it, with the character it types (`"\r"` for Enter, `" "` for
/// Space), so that a focused button is pressed by it as by a person.
pub(crate) async fn press(page: &Page, key: &str, code: &str, key_code: i64, text: &str) -> Result<()> {
    let down = DispatchKeyEventParams::builder()
        .r#type(DispatchKeyEventType::KeyDown)
        .key(key)
        .code(code)
        .windows_virtual_key_code(key_code)
        .text(text)
        .build()?;
    page.execute(down).await?;
    let up = DispatchKeyEventParams::builder()
        .r#type(DispatchKeyEventType::KeyUp)
        .key(key)
        .code(code)
        .windows_virtual_key_code(key_code)
        .build()?;
    page.execute(up).await?;
    settle(page).await
}

/// Types `text` into the field `selector` as a person does: clicks into it, selects what it holds
/// (Ctrl+A), types over it and leaves it with Tab (the change a field reports then).
pub(crate) async fn type_into(page: &Page, selector: &str, text: &str) -> Result<()> {
    let js = format!(
        "(() => {{ const e = document.querySelector({}); if (!e) return false; e.scrollIntoView({{block: 'center'}}); \
         const r = e.getBoundingClientRect(); return [r.left + r.width / 2, r.top + r.height / 2]; }})()",
        serde_json::to_string(selector)?
    );
    let at = eval(page, &js).await?;
    let (x, y) = (at[0].as_f64().ok_or(format!("no field {selector}"))?, at[1].as_f64().ok_or("y")?);
    tap(page, (x, y)).await?;
    key(page, "a", "KeyA", 65, 2).await?;
    if text.is_empty() {
        key(page, "Delete", "Delete", 46, 0).await?;
    } else {
        page.execute(InsertTextParams::new(text)).await?;
    }
    key(page, "Tab", "Tab", 9, 0).await?;
    settle(page).await
}

/// Enter on whatever has the focus.
pub(crate) async fn press_enter(page: &Page) -> Result<()> {
    press(page, "Enter", "Enter", 13, "\r").await
}

/// Space on whatever has the focus.
pub(crate) async fn press_space(page: &Page) -> Result<()> {
    press(page, " ", "Space", 32, " ").await
}

/// Ctrl+Z.
pub(crate) async fn undo(page: &Page) -> Result<()> {
    key(page, "z", "KeyZ", 90, 2).await
}

/// Ctrl+Shift+Z.
pub(crate) async fn redo(page: &Page) -> Result<()> {
    key(page, "Z", "KeyZ", 90, 2 | 8).await
}

/// Panics unless page positions `a` and `b` are the same to half a pixel.
pub(crate) fn assert_same_place(a: (f64, f64), b: (f64, f64)) {
    assert!((a.0 - b.0).abs() < 0.5 && (a.1 - b.1).abs() < 0.5, "{a:?} moved to {b:?}");
}

/// The widest text the control at `selector` shows (a menu's entries, a field's value) and the width
/// of the box it has for it, in pixels.
pub(crate) async fn text_and_room(page: &Page, selector: &str) -> Result<(f64, f64)> {
    let js = format!(
        "(() => {{ const e = document.querySelector('{selector}'); \
         const g = document.createElement('canvas').getContext('2d'); g.font = getComputedStyle(e).font; \
         const texts = e.options ? [...e.options].map((o) => o.text) : [e.value]; \
         return [Math.round(Math.max(...texts.map((t) => g.measureText(t).width))), e.clientWidth]; }})()"
    );
    let [text, room] = serde_json::from_value::<[f64; 2]>(eval(page, &js).await?)?;
    Ok((text, room))
}

/// The screen position of world point (x, y) on the canvas.
pub(crate) async fn at(page: &Page, x: f64, y: f64) -> Result<(f64, f64)> {
    let v = eval(page, &format!("window.linkwright.screenOf([{x}, {y}])")).await?;
    Ok((v[0].as_f64().ok_or("no x")?, v[1].as_f64().ok_or("no y")?))
}

pub(crate) async fn scene(page: &Page) -> Result<Value> {
    eval(page, "JSON.parse(JSON.stringify(window.linkwright.store.scene))").await
}

/// The numbers of a JSON array (integers and floats alike).
pub(crate) fn floats(v: &Value) -> Vec<f64> {
    v.as_array().map(|a| a.iter().filter_map(Value::as_f64).collect()).unwrap_or_default()
}

pub(crate) async fn screenshot(page: &Page, dir: Option<&Path>, name: &str) -> Result<()> {
    if let Some(dir) = dir {
        let png = page.screenshot(ScreenshotParams::builder().format(CaptureScreenshotFormat::Png).build()).await?;
        std::fs::write(dir.join(name), png)?;
    }
    Ok(())
}

/// A browser on the app, served by a server of its own: its page, where downloads go, where
/// screenshots go (if anywhere).
pub(crate) struct App {
    pub page: Page,
    pub server: Server,
    pub downloads: PathBuf,
    pub shots: Option<PathBuf>,
    browser: Browser,
    events: tokio::task::JoinHandle<()>,
    profile: PathBuf,
    errors: Arc<Mutex<Vec<String>>>,
    started: Instant,
    name: &'static str,
}

impl App {
    /// Starts a server and a browser on a blank page (`name` names the test in messages and scratch
    /// folders); `None` when Chromium is missing outside CI (the test is then skipped, with a message).
    pub(crate) async fn launch(name: &'static str) -> Result<Option<App>> {
        let chrome = match chromium() {
            Ok(path) => path,
            Err(missing) if std::env::var("CI").is_ok_and(|v| v == "true") => {
                panic!("Chromium is not installed ({}): CI must install it (see .ci/run)", missing.display())
            }
            Err(missing) => {
                eprintln!(
                    "SKIPPED {name}: Chromium not found at {}; `apt-get install -y chromium` to run it",
                    missing.display()
                );
                return Ok(None);
            }
        };
        let started = Instant::now();
        let shots = std::env::var_os("LINKWRIGHT_SCREENSHOTS").map(PathBuf::from);
        let server = Server::start(&[]);
        let profile = temp_dir(&format!("{name}-profile"));
        let downloads = temp_dir(&format!("{name}-downloads"));
        let config = BrowserConfig::builder()
            .chrome_executable(chrome)
            .no_sandbox()
            .user_data_dir(&profile)
            .window_size(WIDTH, HEIGHT)
            .viewport(Viewport { width: WIDTH, height: HEIGHT, ..Viewport::default() })
            .args([
                "--disable-gpu",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--no-first-run",
                "--enable-unsafe-swiftshader",
            ])
            .build()?;
        let (browser, mut handler) = Browser::launch(config).await?;
        let events = tokio::spawn(async move { while handler.next().await.is_some() {} });
        browser
            .execute(
                SetDownloadBehaviorParams::builder()
                    .behavior(SetDownloadBehaviorBehavior::Allow)
                    .download_path(downloads.to_string_lossy().into_owned())
                    .build()?,
            )
            .await?;
        let page = browser.new_page("about:blank").await?;
        let errors = Arc::new(Mutex::new(Vec::<String>::new()));
        let mut exceptions = page.event_listener::<EventExceptionThrown>().await?;
        let seen = errors.clone();
        tokio::spawn(async move {
            while let Some(e) = exceptions.next().await {
                let d = &e.exception_details;
                let text = d.exception.as_ref().and_then(|x| x.description.clone()).unwrap_or_else(|| d.text.clone());
                if let Ok(mut all) = seen.lock() {
                    all.push(text);
                }
            }
        });
        Ok(Some(App { page, server, downloads, shots, browser, events, profile, errors, started, name }))
    }

    /// Opens the app and waits until it is ready.
    pub(crate) async fn open(&self) -> Result<()> {
        self.page.goto(self.server.url.as_str()).await?;
        until(&self.page, "document.body.dataset.ready === 'true'", Duration::from_secs(10)).await
    }

    /// Closes the browser and gives `outcome`, then fails if the page threw anywhere in the session.
    /// On a failure the page as it was is pictured in the temporary folder.
    pub(crate) async fn finish(mut self, outcome: Result<()>) -> Result<()> {
        if outcome.is_err() {
            let picture = std::env::temp_dir().join(format!("linkwright-{}-failure.png", self.name));
            if let Ok(png) = self.page.screenshot(ScreenshotParams::builder().build()).await {
                let _ = std::fs::write(&picture, png);
                eprintln!("{}: the page at the failure is in {}", self.name, picture.display());
            }
        }
        let errors = self.errors.lock().map(|e| e.clone()).unwrap_or_default();
        self.browser.close().await?;
        let _ = self.browser.wait().await;
        self.events.abort();
        let _ = std::fs::remove_dir_all(&self.profile);
        let _ = std::fs::remove_dir_all(&self.downloads);
        outcome?;
        assert!(errors.is_empty(), "the page threw: {errors:?}");
        eprintln!("{}: done in {:.1} s", self.name, self.started.elapsed().as_secs_f64());
        Ok(())
    }
}

/// The page's size as a window of `width` × `height` pixels.
pub(crate) async fn window_size(page: &Page, width: u32, height: u32) -> Result<()> {
    page.execute(SetDeviceMetricsOverrideParams::new(width, height, 1.0, false)).await?;
    settle(page).await
}

/// Elements of the side panel's tab `tab` that stick out of it sideways (`.tab` scrolls only
/// up and down), as `tag.class` names; none when it fits. The shapes inside a picture are not
/// counted (the picture cuts them), the picture is.
pub(crate) async fn overflowing(page: &Page, tab: &str) -> Result<Vec<String>> {
    let js = format!(
        "(() => {{ const t = document.getElementById('tab-{tab}'), box = t.getBoundingClientRect(); \
         const out = [...t.querySelectorAll('*')].filter((e) => !e.ownerSVGElement).filter((e) => {{ const r = e.getBoundingClientRect(); \
           return r.width > 0 && (r.right > box.right + 0.5 || r.left < box.left - 0.5); }}) \
           .map((e) => `${{e.tagName.toLowerCase()}}.${{e.className}}`); \
         if (t.scrollWidth > t.clientWidth) out.push(`the tab scrolls sideways: ${{t.scrollWidth}} > ${{t.clientWidth}}`); \
         return out; }})()"
    );
    let found = eval(page, &js).await?;
    Ok(found.as_array().into_iter().flatten().filter_map(|v| v.as_str().map(String::from)).collect())
}

/// What does not fit the window as it is: the page scrolling sideways or down, a control of the
/// header, the toolbars, the player, the tabs or the tab shown (where its own scrolling shows it)
/// outside the window or covered by something else, the player sticking out of the drawing. Empty
/// when everything fits.
pub(crate) async fn layout_problems(page: &Page) -> Result<Vec<String>> {
    let js = r#"(() => {
      const out = [], W = innerWidth, H = innerHeight, root = document.documentElement;
      if (root.scrollWidth > W) out.push(`the page scrolls sideways: ${root.scrollWidth} > ${W}`);
      if (root.scrollHeight > H) out.push(`the page scrolls down: ${root.scrollHeight} > ${H}`);
      const tab = [...document.querySelectorAll('.tab')].find((t) => !t.hidden);
      const seen = tab.getBoundingClientRect();
      const name = (e) => e.id || e.getAttribute('aria-label') || e.dataset.key || e.textContent.trim() || e.tagName;
      // The tab's own controls scroll with it: those whose middle it shows are checked for cover.
      const inTab = [...tab.querySelectorAll('button, input, select')].filter((e) => {
        const r = e.getBoundingClientRect(), y = r.top + r.height / 2;
        return y > seen.top && y < seen.bottom;
      });
      const controls = [...document.querySelectorAll('header button, header input, .toolbar button, .toolbar input, '
        + '.posebar button, #player button, #player input, #player select, .tabs button')]
        .concat(inTab)
        .filter((e) => e.checkVisibility() && e.type !== 'file');
      for (const e of controls) {
        const r = e.getBoundingClientRect();
        const outside = r.left < -0.5 || r.right > W + 0.5 || r.top < -0.5 || r.bottom > H + 0.5;
        if (outside && !inTab.includes(e)) {
          out.push(`${name(e)} is outside the window (${Math.round(r.left)}, ${Math.round(r.top)}; the window is ${W} × ${H})`);
          continue;
        }
        const top = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);
        const own = top && (top === e || e.contains(top) || (top.tagName === 'LABEL' && top.contains(e)));
        if (!own) out.push(`${name(e)} is covered by ${top ? name(top) : 'nothing'}`);
      }
      const player = document.getElementById('player');
      if (!player.hidden && player.getBoundingClientRect().right > player.parentElement.getBoundingClientRect().right + 0.5) {
        out.push('the player sticks out of the drawing');
      }
      return out;
    })()"#;
    Ok(serde_json::from_value(eval(page, js).await?)?)
}

pub(crate) async fn wait_for_file(dir: &Path, suffix: &str, within: Duration) -> Result<PathBuf> {
    let start = Instant::now();
    loop {
        if let Some(found) = std::fs::read_dir(dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|p| p.to_string_lossy().ends_with(suffix))
        {
            return Ok(found);
        }
        if start.elapsed() > within {
            return Err(format!("no *{suffix} in {} after {within:?}", dir.display()).into());
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// Chooses `file` in the file input `selector`, as a person does in the file dialog.
pub(crate) async fn choose_file(page: &Page, selector: &str, file: &Path) -> Result<()> {
    let input = page.find_element(selector).await?;
    let params = SetFileInputFilesParams::builder()
        .files(vec![file.to_string_lossy().into_owned()])
        .backend_node_id(input.backend_node_id)
        .build()?;
    page.execute(params).await?;
    settle(page).await
}

/// Answers "Open the example" when the app asks before an example replaces unsaved changes (it asks
/// at once, when the example is chosen).
pub(crate) async fn replace_if_asked(page: &Page) -> Result<()> {
    let js = "(() => { const d = document.getElementById('replace'); \
              if (d.open) document.getElementById('btn-replace').click(); return true; })()";
    eval(page, js).await?;
    settle(page).await
}

/// Designs the scene shown with a quick search (5,000 samples, Settings) and waits for it to play.
pub(crate) async fn design_quickly(page: &Page) -> Result<()> {
    click(page, "[data-tab=settings]").await?;
    click(page, "button[title='5000 samples']").await?;
    click(page, "#btn-design").await?;
    until(page, "!document.getElementById('player').hidden", Duration::from_secs(120)).await
}

/// Picks the design's thumbnail `which` (`best`, or an alternative's index) in the Result tab and
/// waits for its motion.
pub(crate) async fn pick_design(page: &Page, which: &str) -> Result<()> {
    click(page, &format!("#tab-result .thumb[data-which='{which}']")).await?;
    let shown = if which == "best" { "null".to_string() } else { which.to_string() };
    let js =
        format!("window.linkwright.store.result.which === {shown} && window.linkwright.store.result.analysis !== null");
    until(page, &js, Duration::from_secs(10)).await
}
