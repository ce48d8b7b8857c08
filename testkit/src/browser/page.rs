//! One page (a browser tab) and what a test does with it: run JavaScript, wait for a
//! condition or a console message, take a screenshot, touch, click and type.
//!
//! Events (console messages, uncaught exceptions, load progress, a crash) are read whenever
//! the page talks to the browser, so nothing is lost between calls.

use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::image::Rgba;
use super::{keys, Browser, Error};

/// How often [`Page::wait_until`] evaluates its condition.
const POLL: Duration = Duration::from_millis(50);
/// How long [`Page::console`] listens for messages already on their way.
const SETTLE: Duration = Duration::from_millis(20);

/// The size and kind of screen a page is shown on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viewport {
    /// Width in CSS pixels.
    pub width: u32,
    /// Height in CSS pixels.
    pub height: u32,
    /// Device pixels per CSS pixel; screenshots are this many times larger.
    pub device_scale: f64,
    /// Emulates a phone: the page's `<meta name="viewport">` is honoured, scrollbars overlay.
    pub mobile: bool,
    /// Touch events exist (`'ontouchstart' in window`, `navigator.maxTouchPoints > 0`), as
    /// [`Page::touch_drag`] and [`Page::tap`] need.
    pub touch: bool,
}

impl Viewport {
    /// A desktop window of `width` × `height` CSS pixels, one device pixel each, mouse only.
    pub fn desktop(width: u32, height: u32) -> Viewport {
        Viewport {
            width,
            height,
            device_scale: 1.0,
            mobile: false,
            touch: false,
        }
    }

    /// A phone held upright, 390 × 844 CSS pixels (an iPhone 12 to 15), with touch. One
    /// device pixel per CSS pixel keeps screenshots small; set `device_scale` for more.
    pub fn phone() -> Viewport {
        Viewport {
            width: 390,
            height: 844,
            device_scale: 1.0,
            mobile: true,
            touch: true,
        }
    }
}

/// A page opened by [`Browser::open`]; its tab is closed when this is dropped.
pub struct Page<'b> {
    browser: &'b Browser,
    target: String,
    session: String,
    console: Vec<String>,
    /// `(frame id, loader id)` of the documents whose `load` event has fired.
    loaded: Vec<(String, String)>,
    crashed: Option<String>,
}

impl<'b> Page<'b> {
    /// Opens a tab in a window of its own (so that its animation frames run even when other
    /// pages are open), applies `viewport`, then loads `url` and waits for its `load` event.
    pub(crate) fn open(browser: &'b Browser, url: &str, viewport: Viewport) -> Result<Self, Error> {
        let deadline = Instant::now() + browser.timeout;
        let created = browser.call(
            None,
            "Target.createTarget",
            json!({ "url": "about:blank", "newWindow": true }),
            deadline,
        )?;
        let target = string(&created, "targetId", "Target.createTarget")?;
        let attached = browser.call(
            None,
            "Target.attachToTarget",
            json!({ "targetId": target, "flatten": true }),
            deadline,
        );
        let session = match attached {
            Ok(attached) => string(&attached, "sessionId", "Target.attachToTarget")?,
            Err(e) => {
                let _ = browser.call(
                    None,
                    "Target.closeTarget",
                    json!({ "targetId": target }),
                    deadline,
                );
                return Err(e);
            }
        };
        let mut page = Page {
            browser,
            target,
            session,
            console: Vec::new(),
            loaded: Vec::new(),
            crashed: None,
        };
        page.call("Runtime.enable", json!({}))?;
        page.call("Page.enable", json!({}))?;
        page.call("Page.setLifecycleEventsEnabled", json!({ "enabled": true }))?;
        // The page believes it has the focus even when another window has it, so that key
        // events reach it and it does not pause itself as a hidden page would.
        page.call(
            "Emulation.setFocusEmulationEnabled",
            json!({ "enabled": true }),
        )?;
        page.call(
            "Emulation.setDeviceMetricsOverride",
            json!({
                "width": viewport.width,
                "height": viewport.height,
                "deviceScaleFactor": viewport.device_scale,
                "mobile": viewport.mobile,
                "screenWidth": viewport.width,
                "screenHeight": viewport.height,
            }),
        )?;
        if viewport.touch {
            page.call(
                "Emulation.setTouchEmulationEnabled",
                json!({ "enabled": true, "maxTouchPoints": 5 }),
            )?;
        }
        page.navigate(url)?;
        Ok(page)
    }

    /// Loads `url` in this page and waits for its `load` event.
    pub fn navigate(&mut self, url: &str) -> Result<(), Error> {
        let started = Instant::now();
        let answer = self.call("Page.navigate", json!({ "url": url }))?;
        if let Some(error) = answer.get("errorText").and_then(Value::as_str) {
            return Err(Error::Protocol(format!("opening {url}: {error}")));
        }
        let frame = string(&answer, "frameId", "Page.navigate")?;
        let loader = string(&answer, "loaderId", "Page.navigate")?;
        let limit = self.browser.timeout;
        let deadline = started + limit;
        loop {
            if self
                .loaded
                .iter()
                .any(|l| *l == (frame.clone(), loader.clone()))
            {
                return Ok(());
            }
            self.check_alive()?;
            if Instant::now() >= deadline {
                return Err(Error::Timeout(format!(
                    "the load event of {url} did not come within {limit:?}"
                )));
            }
            self.browser.pump(deadline)?;
            self.absorb();
        }
    }

    /// Runs `js` in every document this page loads from now on, before the document's own
    /// scripts (to record what the page does from its first moment: open `about:blank`, add
    /// the script, then [`Page::navigate`]).
    pub fn add_init_script(&mut self, js: &str) -> Result<(), Error> {
        self.call(
            "Page.addScriptToEvaluateOnNewDocument",
            json!({ "source": js }),
        )
        .map(drop)
    }

    /// Evaluates the JavaScript expression `js` in the page and returns its value as JSON
    /// (`null` for `undefined`); a promise is awaited. A thrown exception or a rejected
    /// promise is [`Error::Js`] with its message.
    pub fn eval(&mut self, js: &str) -> Result<Value, Error> {
        self.eval_by(js, Instant::now() + self.browser.timeout)
    }

    /// Waits until the JavaScript expression `condition` is truthy, evaluating it every
    /// 50 ms; fails with [`Error::Timeout`] naming the condition (and the last exception it
    /// threw, if any: a condition may throw while the page is still loading) after `limit`.
    pub fn wait_until(&mut self, condition: &str, limit: Duration) -> Result<(), Error> {
        let deadline = Instant::now() + limit;
        let js = format!("!!({condition})");
        let mut thrown = String::new();
        loop {
            match self.eval_by(&js, deadline) {
                Ok(Value::Bool(true)) => return Ok(()),
                Ok(_) => {}
                Err(Error::Js(e)) => thrown = format!("; it last threw: {e}"),
                Err(Error::Timeout(_)) => {}
                Err(e) => return Err(e),
            }
            if Instant::now() + POLL >= deadline {
                return Err(Error::Timeout(format!(
                    "`{condition}` did not become true within {limit:?}{thrown}"
                )));
            }
            std::thread::sleep(POLL);
        }
    }

    /// Every console message and uncaught exception of the page so far, oldest first, as
    /// `TYPE: TEXT`: TYPE is the console method (`log`, `info`, `warning`, `error`, `debug`,
    /// …) or `exception`, TEXT the arguments joined by spaces (strings as they are, other
    /// values as JSON or their description).
    pub fn console(&mut self) -> Result<Vec<String>, Error> {
        self.browser.pump(Instant::now() + SETTLE)?;
        self.absorb();
        Ok(self.console.clone())
    }

    /// Waits until a console line (see [`Page::console`]) containing `needle` has come, also
    /// one that came before this call, and returns the first such line.
    pub fn wait_for_console(&mut self, needle: &str, limit: Duration) -> Result<String, Error> {
        let deadline = Instant::now() + limit;
        loop {
            self.absorb();
            if let Some(line) = self.console.iter().find(|l| l.contains(needle)) {
                return Ok(line.clone());
            }
            self.check_alive()?;
            if Instant::now() >= deadline {
                let seen = self.console.len();
                let last = self.console.last().cloned().unwrap_or_default();
                return Err(Error::Timeout(format!(
                    "no console message containing {needle:?} within {limit:?} \
                     ({seen} messages, the last: {last:?})"
                )));
            }
            self.browser.pump(deadline)?;
        }
    }

    /// A PNG of what the page shows, at `device_scale` device pixels per CSS pixel.
    pub fn screenshot_png(&mut self) -> Result<Vec<u8>, Error> {
        let shot = self.call(
            "Page.captureScreenshot",
            json!({ "format": "png", "fromSurface": true }),
        )?;
        let data = string(&shot, "data", "Page.captureScreenshot")?;
        data_encoding::BASE64
            .decode(data.as_bytes())
            .map_err(|e| Error::Protocol(format!("a screenshot that is not base64: {e}")))
    }

    /// A screenshot decoded to pixels (see [`Rgba::pixel`]).
    pub fn screenshot(&mut self) -> Result<Rgba, Error> {
        Rgba::from_png(&self.screenshot_png()?)
    }

    /// One finger put down at `from` (CSS pixels from the top left of the viewport), moved to
    /// `to` in `steps` equal moves, and lifted there: `touchstart`, `steps` × `touchmove`,
    /// `touchend`. Needs a viewport with `touch`.
    pub fn touch_drag(
        &mut self,
        from: (f64, f64),
        to: (f64, f64),
        steps: u32,
    ) -> Result<(), Error> {
        self.touch("touchStart", Some(from))?;
        for point in path(from, to, steps) {
            self.touch("touchMove", Some(point))?;
        }
        self.touch("touchEnd", None)
    }

    /// Two fingers put down at `from`, moved together to `to` in `steps` equal moves and
    /// lifted: both down (Chromium fires a `touchstart` for each), `steps` × `touchmove` of
    /// both, both up (a `touchend` for each), with
    /// `pause` after each (a game that follows fingers from frame to frame must see them
    /// down before they move). Both moving the same way is a two-finger drag; apart or
    /// together, a pinch; `from` = `to`, a two-finger tap.
    pub fn two_finger_drag(
        &mut self,
        from: [(f64, f64); 2],
        to: [(f64, f64); 2],
        steps: u32,
        pause: Duration,
    ) -> Result<(), Error> {
        self.touches("touchStart", &from)?;
        std::thread::sleep(pause);
        for (a, b) in path(from[0], to[0], steps).zip(path(from[1], to[1], steps)) {
            self.touches("touchMove", &[a, b])?;
            std::thread::sleep(pause);
        }
        self.touches("touchEnd", &[])?;
        std::thread::sleep(pause);
        Ok(())
    }

    /// A finger put down at `at` and lifted: `touchstart`, `touchend`.
    pub fn tap(&mut self, at: (f64, f64)) -> Result<(), Error> {
        self.touch("touchStart", Some(at))?;
        self.touch("touchEnd", None)
    }

    /// The mouse moved to `at` and its left button pressed and released there.
    pub fn click(&mut self, at: (f64, f64)) -> Result<(), Error> {
        self.mouse("mouseMoved", at, false)?;
        self.mouse("mousePressed", at, true)?;
        self.mouse("mouseReleased", at, false)
    }

    /// The left button pressed at `from`, the mouse moved to `to` in `steps` equal moves with
    /// the button held, and released there.
    pub fn mouse_drag(
        &mut self,
        from: (f64, f64),
        to: (f64, f64),
        steps: u32,
    ) -> Result<(), Error> {
        self.mouse("mouseMoved", from, false)?;
        self.mouse("mousePressed", from, true)?;
        for point in path(from, to, steps) {
            self.mouse("mouseMoved", point, true)?;
        }
        self.mouse("mouseReleased", to, false)
    }

    /// Presses and releases one key, sent to the focused element: a printable ASCII character
    /// (`"a"`, `"7"`, `" "`), or a key name such as `"Enter"`, `"Escape"`, `"Tab"`,
    /// `"Backspace"`, `"ArrowLeft"`, `"Space"`. A key that types text also fires `keypress`.
    pub fn key(&mut self, name: &str) -> Result<(), Error> {
        let Some((key, code, vk, text)) = keys::key(name) else {
            return Err(Error::Protocol(format!("no such key: {name:?}")));
        };
        let mut down = json!({
            "type": if text.is_some() { "keyDown" } else { "rawKeyDown" },
            "key": key, "code": code,
            "windowsVirtualKeyCode": vk, "nativeVirtualKeyCode": vk,
        });
        if let Some(text) = text {
            down["text"] = json!(text);
            down["unmodifiedText"] = json!(text);
        }
        self.call("Input.dispatchKeyEvent", down)?;
        self.call(
            "Input.dispatchKeyEvent",
            json!({
                "type": "keyUp", "key": key, "code": code,
                "windowsVirtualKeyCode": vk, "nativeVirtualKeyCode": vk,
            }),
        )
        .map(drop)
    }

    /// Sends any DevTools command to this page and returns its result, for what this type
    /// does not cover.
    pub fn call(&mut self, method: &str, params: Value) -> Result<Value, Error> {
        let deadline = Instant::now() + self.browser.timeout;
        self.call_by(method, params, deadline)
    }

    fn call_by(&mut self, method: &str, params: Value, deadline: Instant) -> Result<Value, Error> {
        self.check_alive()?;
        let answer = self
            .browser
            .call(Some(&self.session), method, params, deadline);
        self.absorb();
        answer
    }

    fn eval_by(&mut self, js: &str, deadline: Instant) -> Result<Value, Error> {
        let answer = self
            .call_by(
                "Runtime.evaluate",
                json!({
                    "expression": js,
                    "awaitPromise": true,
                    "returnByValue": true,
                    "userGesture": true,
                }),
                deadline,
            )
            .map_err(|e| match e {
                Error::Timeout(what) => Error::Timeout(format!("{what}, evaluating `{js}`")),
                other => other,
            })?;
        if let Some(details) = answer.get("exceptionDetails") {
            return Err(Error::Js(exception_text(details)));
        }
        Ok(answer
            .get("result")
            .and_then(|r| r.get("value"))
            .cloned()
            .unwrap_or(Value::Null))
    }

    fn touch(&mut self, kind: &str, at: Option<(f64, f64)>) -> Result<(), Error> {
        self.touches(kind, at.as_slice())
    }

    /// One touch event with the fingers `at` down (their ids are their places in the list).
    fn touches(&mut self, kind: &str, at: &[(f64, f64)]) -> Result<(), Error> {
        let points: Vec<Value> = at
            .iter()
            .enumerate()
            .map(|(id, (x, y))| {
                json!({ "x": x, "y": y, "id": id, "radiusX": 1, "radiusY": 1, "force": 1 })
            })
            .collect();
        self.call(
            "Input.dispatchTouchEvent",
            json!({ "type": kind, "touchPoints": points }),
        )
        .map(drop)
    }

    fn mouse(&mut self, kind: &str, (x, y): (f64, f64), held: bool) -> Result<(), Error> {
        let pressing = kind != "mouseMoved";
        self.call(
            "Input.dispatchMouseEvent",
            json!({
                "type": kind, "x": x, "y": y,
                "button": if pressing || held { "left" } else { "none" },
                "buttons": if held { 1 } else { 0 },
                "clickCount": if pressing { 1 } else { 0 },
            }),
        )
        .map(drop)
    }

    /// Takes this page's queued events into its console log and load records.
    fn absorb(&mut self) {
        for event in self.browser.take_events(&self.session) {
            let p = &event.params;
            match event.method.as_str() {
                "Runtime.consoleAPICalled" => {
                    let kind = p.get("type").and_then(Value::as_str).unwrap_or("log");
                    let text: Vec<String> = p
                        .get("args")
                        .and_then(Value::as_array)
                        .map(|args| args.iter().map(remote_text).collect())
                        .unwrap_or_default();
                    self.console.push(format!("{kind}: {}", text.join(" ")));
                }
                "Runtime.exceptionThrown" => {
                    let details = p.get("exceptionDetails").unwrap_or(&Value::Null);
                    self.console
                        .push(format!("exception: {}", exception_text(details)));
                }
                "Page.lifecycleEvent" if p.get("name") == Some(&json!("load")) => {
                    let field =
                        |k: &str| p.get(k).and_then(Value::as_str).unwrap_or("").to_string();
                    self.loaded.push((field("frameId"), field("loaderId")));
                }
                "Inspector.targetCrashed" => {
                    self.crashed = Some("the page crashed (its renderer process ended)".into());
                }
                "Inspector.detached" => {
                    let reason = p.get("reason").and_then(Value::as_str).unwrap_or("unknown");
                    self.crashed = Some(format!("the page was detached: {reason}"));
                }
                _ => {}
            }
        }
    }

    fn check_alive(&self) -> Result<(), Error> {
        match &self.crashed {
            Some(why) => Err(Error::Crashed(why.clone())),
            None => Ok(()),
        }
    }
}

impl Drop for Page<'_> {
    fn drop(&mut self) {
        let deadline = Instant::now() + Duration::from_secs(2);
        let _ = self.browser.call(
            None,
            "Target.closeTarget",
            json!({ "targetId": self.target }),
            deadline,
        );
        // Events that came for this page after it was closed would stay queued for good.
        let _ = self.browser.take_events(&self.session);
    }
}

/// The `steps` points after `from` on the way to `to`, the last one `to` itself.
fn path(from: (f64, f64), to: (f64, f64), steps: u32) -> impl Iterator<Item = (f64, f64)> {
    let steps = steps.max(1);
    (1..=steps).map(move |i| {
        let t = f64::from(i) / f64::from(steps);
        (from.0 + (to.0 - from.0) * t, from.1 + (to.1 - from.1) * t)
    })
}

/// The text of a `Runtime.RemoteObject`: a string as it is, another value as JSON, an object
/// by its description.
fn remote_text(object: &Value) -> String {
    match object.get("value") {
        Some(Value::String(s)) => s.clone(),
        Some(value) => value.to_string(),
        None => ["unserializableValue", "description", "type"]
            .iter()
            .find_map(|k| object.get(*k).and_then(Value::as_str))
            .unwrap_or("?")
            .to_string(),
    }
}

/// The message of a `Runtime.ExceptionDetails`: the thrown value's description (for an Error,
/// its name, message and stack), else its value, else the details' own text.
fn exception_text(details: &Value) -> String {
    let exception = details.get("exception");
    exception
        .and_then(|e| e.get("description"))
        .and_then(Value::as_str)
        .map(str::to_string)
        .or_else(|| {
            exception.and_then(|e| e.get("value")).map(|v| match v {
                Value::String(s) => s.clone(),
                other => other.to_string(),
            })
        })
        .or_else(|| {
            details
                .get("text")
                .and_then(Value::as_str)
                .map(str::to_string)
        })
        .unwrap_or_else(|| details.to_string())
}

/// The string field `key` of the answer to `method`.
fn string(answer: &Value, key: &str, method: &str) -> Result<String, Error> {
    answer
        .get(key)
        .and_then(Value::as_str)
        .map(str::to_string)
        .ok_or_else(|| Error::Protocol(format!("{method} answered without {key}: {answer}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_ends_at_its_target_in_equal_steps() {
        let points: Vec<_> = path((0.0, 10.0), (30.0, 40.0), 3).collect();
        assert_eq!(points, vec![(10.0, 20.0), (20.0, 30.0), (30.0, 40.0)]);
        assert_eq!(
            path((0.0, 0.0), (5.0, 5.0), 0).collect::<Vec<_>>(),
            vec![(5.0, 5.0)]
        );
    }

    #[test]
    fn remote_objects_read_as_text() {
        assert_eq!(
            remote_text(&json!({ "type": "string", "value": "hi" })),
            "hi"
        );
        assert_eq!(remote_text(&json!({ "type": "number", "value": 3 })), "3");
        assert_eq!(
            remote_text(&json!({ "type": "object", "description": "Window" })),
            "Window"
        );
        assert_eq!(
            remote_text(&json!({ "type": "number", "unserializableValue": "NaN" })),
            "NaN"
        );
    }

    #[test]
    fn an_exception_reads_as_its_description() {
        let details = json!({ "text": "Uncaught", "exception": { "description": "Error: boom" } });
        assert_eq!(exception_text(&details), "Error: boom");
        assert_eq!(exception_text(&json!({ "text": "Uncaught" })), "Uncaught");
    }
}
