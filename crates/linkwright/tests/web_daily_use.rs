//! The app in a real headless Chromium, used from the keyboard, in a hurry and in a small window:
//! Enter and Space press the focused button (and only it), the toolbar works from Tab alone; opening
//! another scene while a design or its parts are being made drops what they answer for the scene
//! before; at 900 × 700 and 1920 × 1080 nothing scrolls sideways and no control is covered; a saved
//! project opens with its design, alternative, pins, springs and print settings, without a redesign,
//! and a plain scene file still opens; and the small things: Insert pose stops at the engine's most
//! poses (all of them reachable in the pose bar), the kind of shape to draw is not shown chosen while
//! selecting, a part's file is saved under the scene's name, undo and redo of a joint edit bring back
//! that edit's designs, an outline that cannot be a shape is refused with the reason, the labels on
//! the drawing do not cover each other, springs and their brackets are named as the person named the
//! parts, the motion video has every frame, a pose the engine refuses is told in the screen's words,
//! the mass fields show their numbers whole, Live redesign stays ticked after a reload.
//! How the browser is driven, and when the test is skipped: `browser/mod.rs`.

mod browser;
mod common;

use browser::*;
use chromiumoxide::cdp::browser_protocol::input::DispatchMouseEventType;
use chromiumoxide::Page;
use serde_json::Value;
use std::path::Path;
use std::time::Duration;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn keyboard_races_small_windows_and_projects() -> Result<()> {
    let Some(app) = App::launch("web_daily_use").await? else { return Ok(()) };
    let outcome = async {
        app.open().await?;
        keyboard(&app.page).await?;
        races(&app.page).await?;
        windows(&app.page, app.shots.as_deref()).await?;
        projects(&app.page, &app.downloads).await?;
        small_things(&app.page, &app.downloads).await?;
        path_drawn_and_traced(&app.page).await?;
        path_by_points_carried_and_reshaped(&app.page).await?;
        path_exact_points(&app.page).await
    }
    .await;
    app.finish(outcome).await
}

/// True while a design runs.
const DESIGNING: &str = "window.linkwright.results.controller !== null";

/// Focuses the element `selector`.
async fn focus(page: &Page, selector: &str) -> Result<()> {
    let js = format!(
        "(() => {{ const e = document.querySelector({}); e.focus(); return document.activeElement === e; }})()",
        serde_json::to_string(selector)?
    );
    assert_eq!(eval(page, &js).await?, Value::Bool(true), "{selector} takes the focus");
    Ok(())
}

/// The selector-ish name of the focused element.
async fn focused(page: &Page) -> Result<String> {
    let js = "(() => { const e = document.activeElement; return e.id ? `#${e.id}` : e.textContent.trim(); })()";
    Ok(eval(page, js).await?.as_str().unwrap_or_default().to_string())
}

/// Enter and Space on a focused button press it: the Examples button opens the gallery and neither
/// starts a design nor plays; Enter on a gallery entry opens that example; Tab reaches the toolbar's
/// buttons in order; Enter on "Later" moves the pose, Enter on a pose button goes to it and keeps the
/// focus; with nothing focused, Enter still designs.
async fn keyboard(page: &Page) -> Result<()> {
    for (name, text, code, key_code) in [("Enter", "\r", "Enter", 13), (" ", " ", "Space", 32)] {
        focus(page, "#btn-examples").await?;
        press(page, name, code, key_code, text).await?;
        until(page, "document.getElementById('gallery').open", Duration::from_secs(2))
            .await
            .map_err(|e| format!("{name} on Examples: {e}"))?;
        assert_eq!(eval(page, DESIGNING).await?, Value::Bool(false), "{name} on Examples started a design");
        press(page, "Escape", "Escape", 27, "").await?;
        until(page, "!document.getElementById('gallery').open", Duration::from_secs(2)).await?;
    }

    // An example, chosen from the gallery with the keyboard.
    focus(page, "#btn-examples").await?;
    press_enter(page).await?;
    let entry = "[data-example=k1_garbage_truck]";
    until(page, &format!("document.querySelector('{entry} svg') !== null"), Duration::from_secs(10)).await?;
    focus(page, entry).await?;
    press_enter(page).await?;
    until(page, "window.linkwright.store.scene.name === 'garbage truck'", Duration::from_secs(2)).await?;
    assert_eq!(eval(page, DESIGNING).await?, Value::Bool(false));

    // Tab walks the header's buttons in order, from New on.
    focus(page, "#btn-new").await?;
    let mut walked = Vec::new();
    for _ in 0..3 {
        key(page, "Tab", "Tab", 9, 0).await?;
        walked.push(focused(page).await?);
    }
    assert_eq!(walked, ["#btn-open", "#btn-save", "#btn-examples"], "Tab from New");

    // The pose bar: Enter on "Later" makes pose 1 come later (pose 2 is then the current one) and
    // designs nothing; Enter on a pose button goes to that pose and keeps the focus on it.
    let first = eval(page, "JSON.stringify(window.linkwright.store.scene.moving_bodies[0].poses[0])").await?;
    focus(page, "#btn-pose-later").await?;
    press_enter(page).await?;
    until(page, "window.linkwright.store.ui.pose === 1", Duration::from_secs(2)).await?;
    let moved = eval(page, "JSON.stringify(window.linkwright.store.scene.moving_bodies[0].poses[1])").await?;
    assert_eq!(moved, first, "pose 1 came later");
    assert_eq!(eval(page, DESIGNING).await?, Value::Bool(false), "Enter on Later started a design");
    undo(page).await?;
    focus(page, "#pose-buttons button:nth-child(3)").await?;
    press_enter(page).await?;
    until(page, "window.linkwright.store.ui.pose === 2", Duration::from_secs(2)).await?;
    assert_eq!(focused(page).await?, "Pose 3", "the pose button keeps the focus");
    press_space(page).await?;
    assert_eq!(eval(page, DESIGNING).await?, Value::Bool(false));

    // Nothing focused: Enter designs (then Cancel stops it).
    eval(page, "document.activeElement.blur() || true").await?;
    key(page, "Enter", "Enter", 13, 0).await?;
    until(page, DESIGNING, Duration::from_secs(2)).await?;
    click(page, "#btn-cancel").await?;
    until(page, &format!("!({DESIGNING})"), Duration::from_secs(10)).await
}

/// Opens the example `name` from the gallery with the mouse.
async fn open_example(page: &Page, name: &str) -> Result<()> {
    click(page, "#btn-examples").await?;
    until(page, &format!("document.querySelector('[data-example={name}] svg') !== null"), Duration::from_secs(10))
        .await?;
    click(page, &format!("[data-example={name}]")).await?;
    replace_if_asked(page).await
}

/// A path scene (the walking foot) shows its drawn curve. With the Path tool (T) a loop is drawn by
/// hand from the foot's centre; designed, the curve its tracer traces is drawn over it, closed, and
/// along it.
async fn path_drawn_and_traced(page: &Page) -> Result<()> {
    open_example(page, "walking_foot").await?;
    let drawn = "document.querySelectorAll('polygon.drawn-path').length";
    assert_eq!(eval(page, drawn).await?, serde_json::json!(1), "the drawn loop is shown before any design");
    press(page, "t", "KeyT", 84, "t").await?;
    assert_eq!(eval(page, "window.linkwright.store.ui.tool").await?, "path");
    let pose = eval(page, "window.linkwright.store.scene.moving_bodies[0].poses[0]").await?;
    let (x, y) = (pose[0].as_f64().ok_or("no x")?, pose[1].as_f64().ok_or("no y")?);
    let start = at(page, x, y).await?;
    // A hand's loop: round a circle of 70 px above the foot's centre (clear of the ground) and back.
    mouse(page, DispatchMouseEventType::MouseMoved, start.0, start.1, 0).await?;
    mouse(page, DispatchMouseEventType::MousePressed, start.0, start.1, 1).await?;
    for k in 1..=48 {
        let a = std::f64::consts::TAU * f64::from(k) / 48.0;
        let p = (start.0 + 70.0 * a.sin(), start.1 - 70.0 * (1.0 - a.cos()));
        mouse(page, DispatchMouseEventType::MouseMoved, p.0, p.1, 1).await?;
    }
    mouse(page, DispatchMouseEventType::MouseReleased, start.0, start.1, 0).await?;
    settle(page).await?;
    let body = scene(page).await?["moving_bodies"][0].clone();
    assert_eq!(body["path"]["closed"], Value::Bool(true), "a stroke back to its start is a loop: {body}");
    assert_eq!(body["poses"].as_array().map(Vec::len), Some(1), "{body}");
    let tracer = &body["path"]["tracer"];
    assert!(tracer[0].as_f64().unwrap().abs() < 1.0 && tracer[1].as_f64().unwrap().abs() < 1.0, "{tracer}");
    assert!(body["path"]["points"].as_array().is_some_and(|p| p.len() >= 30), "{body}");
    undo(page).await?;
    assert_eq!(scene(page).await?["moving_bodies"][0]["path"]["points"].as_array().map(Vec::len), Some(48));
    redo(page).await?;
    design_quickly(page).await?;
    until(page, "document.querySelector('polyline.traced-path') !== null", Duration::from_secs(10)).await?;
    // The traced curve's points, in screen units, against the drawn loop's: each traced point within
    // 3% of the loop's size of some drawn vertex or edge, and its ends together (once round).
    let js = "(() => { const pts = (el) => el.getAttribute('points').trim().split(/\\s+/).map((p) => p.split(',').map(Number)); \
              const t = pts(document.querySelector('polyline.traced-path')), d = pts(document.querySelector('polygon.drawn-path')); \
              const xs = d.map((p) => p[0]), ys = d.map((p) => p[1]); \
              const size = Math.hypot(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)); \
              const seg = (p, a, b) => { const dx = b[0] - a[0], dy = b[1] - a[1], l = dx * dx + dy * dy; \
                const u = l > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l)) : 0; \
                return Math.hypot(p[0] - a[0] - u * dx, p[1] - a[1] - u * dy); }; \
              const far = Math.max(...t.map((p) => Math.min(...d.map((a, i) => seg(p, a, d[(i + 1) % d.length]))))); \
              const ends = Math.hypot(t[0][0] - t[t.length - 1][0], t[0][1] - t[t.length - 1][1]); \
              return {points: t.length > 20, far: far < 0.05 * size, closed: ends < 0.01 * size}; })()";
    assert_eq!(
        eval(page, js).await?,
        serde_json::json!({"points": true, "far": true, "closed": true}),
        "the traced loop follows the drawn one"
    );
    Ok(())
}

/// The world point under page position `p`.
async fn world_at(page: &Page, p: (f64, f64)) -> Result<(f64, f64)> {
    let w = eval(page, &format!("window.linkwright.worldOf([{}, {}])", p.0, p.1)).await?;
    Ok((w[0].as_f64().ok_or("no x")?, w[1].as_f64().ok_or("no y")?))
}

/// The path tool by clicked points: a click on the foot, four points round a square, a click on the
/// first closes a smooth loop through them all. Nudging the foot carries the loop with it; dragging
/// the loop bends it near the grab and leaves its far side and the foot on its start; undo puts it
/// back.
async fn path_by_points_carried_and_reshaped(page: &Page) -> Result<()> {
    open_example(page, "walking_foot").await?;
    press(page, "t", "KeyT", 84, "t").await?;
    let pose = eval(page, "window.linkwright.store.scene.moving_bodies[0].poses[0]").await?;
    let start = at(page, pose[0].as_f64().ok_or("no x")?, pose[1].as_f64().ok_or("no y")?).await?;
    let corners =
        [start, (start.0 + 80.0, start.1 - 10.0), (start.0 + 90.0, start.1 - 90.0), (start.0 - 10.0, start.1 - 80.0)];
    for &c in &corners {
        tap(page, c).await?;
    }
    tap(page, start).await?;
    let body = scene(page).await?["moving_bodies"][0].clone();
    assert_eq!(body["path"]["closed"], Value::Bool(true), "a click on the first point closes the loop: {body}");
    let points: Vec<(f64, f64)> = body["path"]["points"]
        .as_array()
        .ok_or("no points")?
        .iter()
        .map(|p| (p[0].as_f64().unwrap_or(f64::NAN), p[1].as_f64().unwrap_or(f64::NAN)))
        .collect();
    assert!(points.len() >= 40, "a smooth curve, not the four corners: {} points", points.len());
    for &c in &corners[1..] {
        let w = world_at(page, c).await?;
        let near = points.iter().map(|p| (p.0 - w.0).hypot(p.1 - w.1)).fold(f64::INFINITY, f64::min);
        assert!(near < 0.01, "the curve passes through each clicked point: {w:?} is {near} away");
    }

    // Nudged right, the foot takes its loop along: every point moves as far as the pose.
    press(page, "v", "KeyV", 86, "v").await?;
    key(page, "ArrowRight", "ArrowRight", 39, 0).await?;
    settle(page).await?;
    let moved = scene(page).await?["moving_bodies"][0].clone();
    let dx = moved["poses"][0][0].as_f64().ok_or("no x")? - body["poses"][0][0].as_f64().ok_or("no x")?;
    assert!(dx > 0.0, "the arrow moved the foot: {moved}");
    for (a, b) in body["path"]["points"].as_array().unwrap().iter().zip(moved["path"]["points"].as_array().unwrap()) {
        let (ax, bx) = (a[0].as_f64().unwrap(), b[0].as_f64().unwrap());
        let (ay, by) = (a[1].as_f64().unwrap(), b[1].as_f64().unwrap());
        assert!((bx - ax - dx).abs() < 0.01 && (by - ay).abs() < 1e-9, "{a} → {b}, not by {dx}");
    }

    // The loop's far corner dragged 40 px right: it follows, the side opposite stays, the foot stays
    // on the loop's start.
    let far = corners[2];
    let before = world_at(page, far).await?;
    let grab = at(page, before.0 + dx, before.1).await?;
    drag(page, grab, (grab.0 + 40.0, grab.1)).await?;
    let bent = scene(page).await?["moving_bodies"][0].clone();
    let shift = |k: usize| {
        let (a, b) = (&moved["path"]["points"][k], &bent["path"]["points"][k]);
        (b[0].as_f64().unwrap() - a[0].as_f64().unwrap()).hypot(b[1].as_f64().unwrap() - a[1].as_f64().unwrap())
    };
    let n = points.len();
    let most = (0..n).map(shift).fold(0.0, f64::max);
    let step = world_at(page, (40.0, 0.0)).await?.0 - world_at(page, (0.0, 0.0)).await?.0;
    assert!((most - step).abs() < 0.2 * step, "the grabbed point follows the pointer: {most} of {step}");
    assert!(shift(0) < 0.05 * step, "the loop's start, where the foot is, stays: {}", shift(0));
    let tracer = &bent["path"]["tracer"];
    let p = &bent["poses"][0];
    let (c, s) = (p[2].as_f64().unwrap().to_radians().cos(), p[2].as_f64().unwrap().to_radians().sin());
    let (tx, ty) = (tracer[0].as_f64().unwrap(), tracer[1].as_f64().unwrap());
    let world = (p[0].as_f64().unwrap() + c * tx - s * ty, p[1].as_f64().unwrap() + s * tx + c * ty);
    let first = &bent["path"]["points"][0];
    assert!(
        (world.0 - first[0].as_f64().unwrap()).hypot(world.1 - first[1].as_f64().unwrap()) < 0.01,
        "the tracer is on the path's start: {world:?}, {first}"
    );
    undo(page).await?;
    assert_eq!(scene(page).await?["moving_bodies"][0]["path"], moved["path"], "undo unbends the loop");

    // Live redesign: designed once, the loop bent again is designed for anew as it is let go.
    design_quickly(page).await?;
    // On, whatever an earlier step left it.
    let live = "(() => { const e = document.getElementById('opt-live'); if (!e.checked) e.click(); return window.linkwright.store.ui.live; })()";
    assert_eq!(eval(page, live).await?, Value::Bool(true), "live redesign is on");
    // The design's view may have moved: the far corner found on screen anew.
    let grab = at(page, before.0 + dx, before.1).await?;
    drag(page, grab, (grab.0 + 40.0, grab.1)).await?;
    let bent = scene(page).await?["moving_bodies"][0]["path"]["points"].clone();
    assert_ne!(bent, moved["path"]["points"], "the loop is bent again");
    let js = format!(
        "JSON.stringify(window.linkwright.store.result?.scene?.moving_bodies?.[0]?.path?.points) === JSON.stringify({bent}) \
         && window.linkwright.store.result.design.status === 'ok'"
    );
    until(page, &js, Duration::from_secs(60)).await.map_err(|e| format!("no live design for the bent loop: {e}"))?;
    Ok(())
}

/// The walking foot's path with points to pass exactly: a double-click on the drawn path marks the
/// point there (a ring on it, and the Object tab lists it), another frees it again; points typed in
/// the Object tab are marked, a number that is not a point is refused in words; designed, the badge
/// says how closely the exact points are passed, and the file's own measure agrees.
async fn path_exact_points(page: &Page) -> Result<()> {
    open_example(page, "walking_foot").await?;
    press(page, "v", "KeyV", 86, "v").await?;
    let exact = "JSON.stringify(window.linkwright.store.scene.moving_bodies[0].path.exact ?? [])";
    let point = |k: usize| format!("window.linkwright.store.scene.moving_bodies[0].path.points[{k}]");
    let p = eval(page, &point(20)).await?;
    let on_screen = at(page, p[0].as_f64().ok_or("no x")?, p[1].as_f64().ok_or("no y")?).await?;
    double_tap(page, on_screen).await?;
    assert_eq!(eval(page, exact).await?, "[20]", "a double-click marks the point there");
    assert_eq!(eval(page, "document.querySelectorAll('.exact-point').length").await?, serde_json::json!(1));
    let before = eval(page, &point(20)).await?;
    assert_eq!(before, p, "a double-click does not bend the path");
    double_tap(page, on_screen).await?;
    assert_eq!(eval(page, exact).await?, "[]", "a second double-click frees it");
    undo(page).await?;
    assert_eq!(eval(page, exact).await?, "[20]", "undo marks it again");

    // Typed in the Object tab: the list is the points' numbers, from 1.
    click(page, "[data-tab=object]").await?;
    eval(page, "document.querySelectorAll('#tab-object .list')[1].querySelector('.row').click()").await?;
    settle(page).await?;
    let field = "[data-key=exact-0]";
    assert_eq!(eval(page, &format!("document.querySelector('{field}').value")).await?, "21");
    type_into(page, field, "1, 21 40, 99").await?;
    assert_eq!(eval(page, exact).await?, "[20]", "99 is not a point of a 48-point path");
    let hint = eval(page, "document.getElementById('hint').textContent").await?;
    assert!(hint.as_str().is_some_and(|h| h.contains("“99” is not a point of the path")), "{hint}");
    type_into(page, field, "1, 21 40").await?;
    assert_eq!(eval(page, exact).await?, "[0,20,39]");

    // A later pose the foot must pass: inserted with its tracer on the path, turned in the Object tab
    // about its tracer, nudged along the path (never off it).
    click(page, "#btn-pose-insert").await?;
    let off_path =
        "(() => { const b = window.linkwright.store.scene.moving_bodies[0], t = b.path.tracer, pts = b.path.points; \
        const [x, y, a] = b.poses[1], r = a * Math.PI / 180; \
        const w = [x + Math.cos(r) * t[0] - Math.sin(r) * t[1], y + Math.sin(r) * t[0] + Math.cos(r) * t[1]]; \
        const seg = (p, q) => { const dx = q[0] - p[0], dy = q[1] - p[1], l = dx * dx + dy * dy; \
          const u = l > 0 ? Math.max(0, Math.min(1, ((w[0] - p[0]) * dx + (w[1] - p[1]) * dy) / l)) : 0; \
          return Math.hypot(w[0] - p[0] - u * dx, w[1] - p[1] - u * dy); }; \
        return Math.min(...pts.map((p, i) => seg(p, pts[(i + 1) % pts.length]))); })()";
    let on = |v: Value| v.as_f64().is_some_and(|d| d < 0.01);
    assert!(on(eval(page, off_path).await?), "the inserted pose's tracer is on the path");
    type_into(page, "[data-key=pose-0-1-a]", "15").await?;
    let second = eval(page, "window.linkwright.store.scene.moving_bodies[0].poses[1]").await?;
    assert_eq!(second[2], serde_json::json!(15), "{second}");
    assert!(on(eval(page, off_path).await?), "turned about its tracer, which stays on the path");
    eval(page, "document.activeElement.blur()").await?;
    key(page, "ArrowRight", "ArrowRight", 39, 0).await?;
    settle(page).await?;
    let nudged = eval(page, "window.linkwright.store.scene.moving_bodies[0].poses[1]").await?;
    assert_ne!(nudged, second, "the arrow moved the pose");
    assert!(on(eval(page, off_path).await?), "nudged along the path, not off it: {nudged}");

    design_quickly(page).await?;
    click(page, "[data-tab=result]").await?;
    let badge = eval(page, "document.querySelector('#tab-result .badge.verified')?.textContent ?? ''").await?;
    let badge = badge.as_str().unwrap_or_default().to_string();
    let written = eval(page, "window.linkwright.store.result.design.metrics.path_error.exact").await?;
    let rel = written["distance_rel"].as_f64().ok_or(format!("no exact miss written: {written}"))?;
    assert!(rel <= linkwright_core::EXACT_POINT_TOLERANCE, "the three points are passed: {written}");
    let worst = eval(page, "window.linkwright.store.result.design.metrics.worst_pose_error").await?;
    assert!(worst["position_rel_d"].as_f64().is_some_and(|r| r <= 0.01), "both poses are reached: {worst}");
    let rows = "document.querySelectorAll('#tab-result table.pose-errors tbody tr').length";
    assert_eq!(eval(page, rows).await?, serde_json::json!(2), "the poses' table lists both");
    assert!(
        badge.contains("traces the drawn path within") && badge.contains("passing its exact points within"),
        "{badge}"
    );
    Ok(())
}

/// A design running for the wall bed when the sofa bed is opened is stopped, and nothing of it shows
/// on the sofa bed; so are parts being made for the sofa bed's design when the table is opened.
async fn races(page: &Page) -> Result<()> {
    open_example(page, "k2_wall_bed").await?;
    click(page, "#btn-design").await?;
    until(page, DESIGNING, Duration::from_secs(2)).await?;
    open_example(page, "k1_sofa_bed").await?;
    let sofa = eval(page, "window.linkwright.store.scene.name").await?;
    // Long enough for the wall bed's design to have come back, had it not been stopped.
    tokio::time::sleep(Duration::from_secs(3)).await;
    settle(page).await?;
    assert_eq!(eval(page, DESIGNING).await?, Value::Bool(false), "the wall bed's design was stopped");
    assert_eq!(eval(page, "window.linkwright.store.result").await?, Value::Null, "no result for the sofa bed");
    assert_eq!(eval(page, "document.getElementById('player').hidden").await?, Value::Bool(true));
    assert_eq!(eval(page, "window.linkwright.store.scene.name").await?, sofa);

    // The sofa bed designed; its parts asked for, and the table opened from the gallery at once (the
    // gallery is open before, so the parts are still being made when it is chosen).
    design_quickly(page).await?;
    assert_eq!(eval(page, "window.linkwright.store.result.scene.name").await?, sofa);
    click(page, "[data-tab=result]").await?;
    click(page, "#btn-examples").await?;
    until(page, "document.querySelector('[data-example=k1_table] svg') !== null", Duration::from_secs(10)).await?;
    let js = "(() => { document.getElementById('btn-fabricate').click(); const making = window.linkwright.results.fab.job !== null; \
              document.querySelector('[data-example=k1_table]').click(); return making; })()";
    assert_eq!(eval(page, js).await?, Value::Bool(true), "the parts were being made when the table was opened");
    replace_if_asked(page).await?;
    until(page, "window.linkwright.results.fab.job === null", Duration::from_secs(60)).await?;
    tokio::time::sleep(Duration::from_secs(1)).await;
    settle(page).await?;
    let shown = "(() => { const f = window.linkwright.results.fab; return {made: f.made, error: f.error, \
                 links: document.querySelectorAll('a[data-file]').length, view3d: !document.getElementById('view3d').hidden}; })()";
    assert_eq!(
        eval(page, shown).await?,
        serde_json::json!({"made": null, "error": null, "links": 0, "view3d": false}),
        "nothing of the sofa bed's parts stays"
    );
    assert_eq!(eval(page, "window.linkwright.store.scene.name").await?, "table");
    Ok(())
}

/// At 900 × 700 and at 1920 × 1080, with a design playing, on every tab (the Result tab scrolled to
/// its joints), and while a design runs: nothing scrolls sideways, no control is covered.
async fn windows(page: &Page, shots: Option<&std::path::Path>) -> Result<()> {
    design_quickly(page).await?;
    for (width, height) in [(900, 700), (1920, 1080)] {
        window_size(page, width, height).await?;
        for tab in ["object", "settings", "result"] {
            click(page, &format!("[data-tab={tab}]")).await?;
            if tab == "result" {
                eval(page, "document.querySelector('#tab-result table.joint-table').scrollIntoView() || true").await?;
                settle(page).await?;
            }
            let problems = layout_problems(page).await?;
            assert!(problems.is_empty(), "{tab} tab at {width} × {height}: {problems:?}");
            screenshot(page, shots, &format!("window_{tab}_{width}x{height}.png")).await?;
        }
        // While a design runs, its progress takes the Design button's place in the header.
        click(page, "#btn-design").await?;
        until(page, DESIGNING, Duration::from_secs(2)).await?;
        let problems = layout_problems(page).await?;
        screenshot(page, shots, &format!("window_designing_{width}x{height}.png")).await?;
        click(page, "#btn-cancel").await?;
        until(page, &format!("!({DESIGNING})"), Duration::from_secs(10)).await?;
        assert!(problems.is_empty(), "designing at {width} × {height}: {problems:?}");
    }
    window_size(page, WIDTH, HEIGHT).await
}

/// What a project keeps, as the app holds it: the scene, the design and the mechanism shown, the
/// springs suggested and the print settings, each as JSON text.
const KEPT: &str = "(() => { const l = window.linkwright, r = l.store.result; return { \
    scene: JSON.stringify(l.store.scene), design: JSON.stringify(r?.design ?? null), which: r?.which ?? null, \
    balance: JSON.stringify(r?.balance ?? null), print: JSON.stringify(l.results.fab.print) }; })()";

/// The table designed (by `windows`), its first alternative chosen, a joint pinned, a print setting
/// typed and springs suggested; saved with Ctrl+S; a new scene; the saved file opened: everything as
/// it was, with no request to design. Then the bundled table's plain scene file opens as a scene.
async fn projects(page: &Page, downloads: &Path) -> Result<()> {
    click(page, "[data-tab=result]").await?;
    pick_design(page, "0").await?;
    click(page, "input[data-pin]").await?;
    until(page, "Object.keys(window.linkwright.store.scene.pinned_joints || {}).length === 1", Duration::from_secs(2))
        .await?;
    let js = "(() => { const d = document.querySelector('details.print-settings'); d.open = true; \
              const i = d.querySelector('input'); i.value = '12'; i.dispatchEvent(new Event('change')); return true; })()";
    eval(page, js).await?;
    click(page, "[data-action=springs]").await?;
    until(page, "window.linkwright.store.result.balance != null", Duration::from_secs(60)).await?;
    let before = eval(page, KEPT).await?;
    assert_eq!(before["which"], 0, "{before}");
    assert!(before["print"].as_str().unwrap_or_default().contains("12"), "{before}");
    assert_ne!(before["balance"], "null");

    key(page, "s", "KeyS", 83, 2).await?;
    let saved = wait_for_file(downloads, "table.json", Duration::from_secs(10)).await?;
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&saved)?)?;
    assert_eq!(file["linkwright"], "project/1");
    click(page, "#btn-new").await?;
    assert_eq!(eval(page, "window.linkwright.store.result").await?, Value::Null);
    // Every request to design counted from here.
    eval(page, "(() => { window.designRequests = 0; const f = window.fetch; window.fetch = (u, o) => { \
                if (String(u).startsWith('/api/design')) window.designRequests += 1; return f(u, o); }; return true; })()").await?;
    choose_file(page, "#file-input", &saved).await?;
    until(
        page,
        "window.linkwright.store.result?.analysis != null && window.linkwright.store.result.balance != null",
        Duration::from_secs(10),
    )
    .await?;
    let after = eval(page, KEPT).await?;
    for field in ["scene", "design", "which", "balance", "print"] {
        let (a, b) = (after[field].to_string(), before[field].to_string());
        let at = a.chars().zip(b.chars()).take_while(|(x, y)| x == y).count();
        let around = |t: &str| t.chars().skip(at.saturating_sub(80)).take(160).collect::<String>();
        assert!(a == b, "{field} differs after opening the project, at {at}: {} against {}", around(&a), around(&b));
    }
    assert_eq!(eval(page, "window.designRequests").await?, 0, "opening a project designs nothing");
    assert_eq!(
        eval(page, "document.getElementById('player').hidden").await?,
        Value::Bool(false),
        "its design is shown"
    );

    // A plain scene file, as the CLI and older versions write them.
    let plain = downloads.join("plain_table.json");
    std::fs::copy(format!("{}/../../examples/k1_table.json", env!("CARGO_MANIFEST_DIR")), &plain)?;
    choose_file(page, "#file-input", &plain).await?;
    until(
        page,
        "window.linkwright.store.result === null && window.linkwright.store.scene.name === 'table'",
        Duration::from_secs(5),
    )
    .await?;
    assert_eq!(eval(page, "window.linkwright.store.scene.pinned_joints ?? null").await?, Value::Null);
    Ok(())
}

/// The small things, on the table, then on the examples that show each best.
async fn small_things(page: &Page, downloads: &Path) -> Result<()> {
    // Parts: each part's file is saved under the scene's name.
    design_quickly(page).await?;
    click(page, "[data-tab=result]").await?;
    click(page, "#btn-fabricate").await?;
    until(page, "document.querySelector('a[data-file^=\"parts/\"]') !== null", Duration::from_secs(60)).await?;
    let names = eval(page, "[...document.querySelectorAll('a[data-file^=\"parts/\"]')].map((a) => a.download)").await?;
    let names: Vec<&str> = names.as_array().ok_or("names")?.iter().filter_map(Value::as_str).collect();
    assert!(!names.is_empty() && names.iter().all(|n| n.starts_with("table_") && n.ends_with(".stl")), "{names:?}");

    // The pose errors name their measure, and the charts' tick labels lie inside the charts.
    let header = "document.querySelector('table.pose-errors thead th:nth-child(3)').textContent";
    assert_eq!(eval(page, header).await?, "of width");
    let clipped = "[...document.querySelectorAll('#tab-result svg.plot .axes text')].filter((t) => t.getBBox().x < 0) \
                   .map((t) => t.textContent)";
    assert_eq!(eval(page, clipped).await?, serde_json::json!([]), "tick labels cut at the chart's edge");
    let labels = eval(page, "document.querySelectorAll('#tab-result svg.plot .axes text').length").await?;
    assert!(labels.as_u64() > Some(0), "the charts are shown");
    // Errors of a few nanometres, as an exact design has: their labels fit too.
    let tiny = "import('/js/plots.js').then((m) => { const chart = m.errorPlot({poses: [{pose: 0, bodies: \
                [{max_vertex: 3e-9, angle_deg: 0}]}, {pose: 1, bodies: [{max_vertex: 1e-9, angle_deg: 0}]}]}, \
                {units: 'mm', moving_bodies: [{name: 'lid'}]}); document.getElementById('tab-result').append(chart); \
                const cut = [...chart.querySelectorAll('.axes text')].filter((t) => t.getBBox().x < 0).map((t) => t.textContent); \
                chart.remove(); return cut; })";
    assert_eq!(eval(page, tiny).await?, serde_json::json!([]), "tiny errors' tick labels are cut");

    // A design the engine marks far from a pose (`far_from_pose`) is not shown as an approximation: its
    // badge says it is far from the drawing, and that nothing closer was found.
    let badge = |far: &str| {
        format!(
            "import('/js/accuracy.js').then((m) => {{ const scene = {{units: 'mm', moving_bodies: [{{name: 'lid', \
             polygon: [[0, 0], [10, 0], [10, 5]], poses: [[0, 0, 0], [5, 0, 0]]}}]}}; \
             const miss = (p, r, a) => ({{position: p, position_rel_d: r, angle_deg: a}}); \
             const metrics = {{pose_errors: [[miss(0, 0, 0)], [miss(2, 0.4, 7)]], far_from_pose: {far}}}; \
             const b = m.reachBadge(m.poseErrors(metrics, null, scene), scene); return [b.className, b.textContent]; }})"
        )
    };
    let far = eval(page, &badge("{pose: 2, body: 'lid', position: 2, position_rel_d: 0.4, angle_deg: 7}")).await?;
    assert_eq!(
        far,
        serde_json::json!([
            "badge far verified",
            "Far from the drawing: Pose 2 (lid) is missed by 2.0 mm (40% of its width) and 7.0°, and no linkage closer was found"
        ])
    );
    let near = eval(page, &badge("undefined")).await?;
    assert_eq!(near[0], "badge warn verified", "{near}");
    motion_video_frames(page, downloads).await?;

    // The engine's reasons are shown in the screen's words, not the file's.
    let words =
        "import('/js/fields.js').then((m) => m.screenWords('Raise settings.pose_tolerance (now 0.05), widen the \
                 linkage_region, or move moving_bodies[0].poses[2]', window.linkwright.store.scene))";
    assert_eq!(
        eval(page, words).await?,
        "Raise “Settings › Pose tolerance” (now 0.05), widen the linkage region, or move Moving body “body1”, pose 3"
    );

    // Picking an alternative far down the Result tab keeps the tab where it was scrolled to.
    click(page, "[data-tab=result]").await?;
    eval(page, "document.querySelector('[data-which=\"1\"]').scrollIntoView() || true").await?;
    settle(page).await?;
    let scrolled = eval(page, "document.getElementById('tab-result').scrollTop").await?.as_f64().ok_or("scrollTop")?;
    assert!(scrolled > 0.0, "the alternatives are below the fold");
    pick_design(page, "1").await?;
    settle(page).await?;
    let now = eval(page, "document.getElementById('tab-result').scrollTop").await?.as_f64().ok_or("scrollTop")?;
    assert!((now - scrolled).abs() < 1.0, "the Result tab scrolled from {scrolled} to {now}");
    // The status line says which design is shown now.
    until(page, "window.linkwright.store.ui.hint.startsWith('Alternative 2: ')", Duration::from_secs(5)).await?;

    // F frames everything above the player; renaming a body keeps the design.
    key(page, "f", "KeyF", 70, 0).await?;
    let above = "(() => { const l = window.linkwright, s = l.store.scene, pts = s.fixed_bodies.flatMap((b) => b.polygon); \
                 for (const b of s.moving_bodies) for (const [x, y, a] of b.poses) { const c = Math.cos(a * Math.PI / 180), \
                 n = Math.sin(a * Math.PI / 180); for (const [u, v] of b.polygon) pts.push([x + c * u - n * v, y + n * u + c * v]); } \
                 const bottom = Math.max(...pts.map((p) => l.screenOf(p)[1])); \
                 return bottom <= document.getElementById('player').getBoundingClientRect().top; })()";
    assert_eq!(eval(page, above).await?, Value::Bool(true), "F puts the drawing under the player");
    click(page, "[data-tab=object]").await?;
    let rename = "(() => { const i = document.querySelector('[data-key=moving-name-0]'); i.value = 'leaf'; \
                  i.dispatchEvent(new Event('change')); return true; })()";
    eval(page, rename).await?;
    assert_eq!(eval(page, "window.linkwright.results.fresh()").await?, Value::Bool(true), "renaming kept the design");
    joint_edit_undone_and_redone(page).await?;

    // Poses up to the engine's limit, every one reachable in the pose bar, and no more.
    let most = eval(page, "fetch('/api/status').then((r) => r.json()).then((s) => s.limits.poses_per_body)").await?;
    let most = most.as_u64().ok_or("the limit on poses")? as usize;
    click(page, "#btn-edit").await?;
    let count = "window.linkwright.store.scene.moving_bodies[0].poses.length";
    loop {
        let n = eval(page, count).await?.as_u64().ok_or("poses")? as usize;
        if n >= most {
            break;
        }
        click(page, "#btn-pose-insert").await?;
    }
    assert_eq!(eval(page, count).await?.as_u64(), Some(most as u64));
    assert_eq!(eval(page, "document.getElementById('btn-pose-insert').disabled").await?, Value::Bool(true));
    for (width, height) in [(900, 700), (1920, 1080)] {
        window_size(page, width, height).await?;
        let problems = layout_problems(page).await?;
        assert!(problems.is_empty(), "{most} poses at {width} × {height}: {problems:?}");
        click(page, &format!("#pose-buttons button:nth-child({most})")).await?;
        assert_eq!(eval(page, "window.linkwright.store.ui.pose").await?.as_u64(), Some(most as u64 - 1));
    }
    window_size(page, WIDTH, HEIGHT).await?;

    // Selecting: no kind of shape shown chosen; a shape tool: the kind it draws.
    click(page, "[data-tool=select]").await?;
    assert_eq!(eval(page, "document.querySelectorAll('[data-kind-choice].on').length").await?, 0);
    click(page, "[data-tool=rect]").await?;
    assert_eq!(eval(page, "document.querySelectorAll('[data-kind-choice].on').length").await?, 1);

    // The pointer's place is given in the scene's units, at once when they change.
    let over = at(page, 10.0, 10.0).await?;
    mouse(page, DispatchMouseEventType::MouseMoved, over.0, over.1, 0).await?;
    until(page, "document.getElementById('coords').textContent.endsWith(' mm')", Duration::from_secs(2)).await?;
    let units = "(() => { const s = document.querySelector('select[data-key=units]'); s.value = 'cm'; \
                 s.dispatchEvent(new Event('change')); return true; })()";
    for tab in ["object", "settings"] {
        click(page, &format!("[data-tab={tab}]")).await?;
        if eval(page, "document.querySelector('select[data-key=units]') !== null").await? == Value::Bool(true) {
            eval(page, units).await?;
            break;
        }
    }
    until(page, "document.getElementById('coords').textContent.endsWith(' cm')", Duration::from_secs(2)).await?;
    undo(page).await?;
    outlines_refused(page).await?;

    labels_apart(page).await?;
    springs_named(page).await?;
    pose_in_screen_words(page).await?;
    masses_fit(page).await?;

    // An example replaces a drawing with unsaved changes only after asking: kept, then replaced.
    let renamed = "(() => { const s = window.linkwright.store; s.edit('rename', (x) => { x.name = 'my table'; }); return true; })()";
    eval(page, renamed).await?;
    click(page, "#btn-examples").await?;
    until(page, "document.querySelector('[data-example=k1_sofa_bed] svg') !== null", Duration::from_secs(10)).await?;
    click(page, "[data-example=k1_sofa_bed]").await?;
    until(page, "document.getElementById('replace').open", Duration::from_secs(2)).await?;
    click(page, "#btn-replace-keep").await?;
    assert_eq!(eval(page, "window.linkwright.store.scene.name").await?, "my table", "the drawing is kept");
    open_example(page, "k1_sofa_bed").await?;
    assert_eq!(eval(page, "window.linkwright.store.scene.name").await?, "sofa bed");
    // Unchanged since it was opened: the next example opens without asking.
    click(page, "#btn-examples").await?;
    until(page, "document.querySelector('[data-example=k1_table] svg') !== null", Duration::from_secs(10)).await?;
    click(page, "[data-example=k1_table]").await?;
    assert_eq!(eval(page, "document.getElementById('replace').open").await?, Value::Bool(false));
    assert_eq!(eval(page, "window.linkwright.store.scene.name").await?, "table");

    // Live redesign, ticked, stays ticked after a reload.
    click(page, "#opt-live").await?;
    assert_eq!(eval(page, "document.getElementById('opt-live').checked").await?, Value::Bool(true));
    tokio::time::sleep(Duration::from_millis(400)).await;
    page.reload().await?;
    until(page, "document.body.dataset.ready === 'true'", Duration::from_secs(10)).await?;
    assert_eq!(eval(page, "document.getElementById('opt-live').checked").await?, Value::Bool(true));
    Ok(())
}

/// The shown design's joints, as JSON text.
const JOINTS: &str = "JSON.stringify(window.linkwright.store.result.mechanism.joints)";

/// A joint of the design shown moved by typing its x (a place a few tenths away, one way or the
/// other: the linkage may not follow every move); another design made after it; undo gives back the
/// design before the edit, redo the edited one, not the design made since.
async fn joint_edit_undone_and_redone(page: &Page) -> Result<()> {
    click(page, "[data-tab=result]").await?;
    let before = eval(page, JOINTS).await?;
    let name = eval(page, "document.querySelector('#tab-result input[data-joint-x]').dataset.jointX").await?;
    let name = name.as_str().ok_or("a joint in the Joints table")?.to_string();
    let settled = format!(
        "!window.linkwright.results.joints.editBusy && /^Joint {name} (at|cannot go)/.test(window.linkwright.store.ui.hint)"
    );
    let mut edited = None;
    for step in [0.3, -0.3, 0.6, -0.6, 1.0, -1.0] {
        let x = eval(page, &format!("window.linkwright.store.result.mechanism.joints.{name}[0]")).await?;
        let typed = ((x.as_f64().ok_or("x")? + step) * 10.0).round() / 10.0;
        eval(page, "(window.linkwright.store.ui.hint = '') || true").await?;
        type_into(page, &format!("#tab-result input[data-joint-x={name}]"), &typed.to_string()).await?;
        until(page, &settled, Duration::from_secs(10)).await?;
        let hint = eval(page, "window.linkwright.store.ui.hint").await?;
        if hint.as_str().is_some_and(|h| h.starts_with(&format!("Joint {name} at"))) {
            edited = Some(eval(page, JOINTS).await?);
            break;
        }
    }
    let edited = edited.ok_or(format!("no small move of joint {name} was taken"))?;
    assert_ne!(edited, before);
    // Designed again: the edited design has no alternatives, the new one has.
    click(page, "#btn-design").await?;
    let designed = format!(
        "!({DESIGNING}) && window.linkwright.store.result.analysis !== null && \
         window.linkwright.store.result.design.alternatives.length > 0"
    );
    until(page, &designed, Duration::from_secs(60)).await?;
    eval(page, "document.activeElement.blur() || true").await?;
    undo(page).await?;
    assert_eq!(eval(page, JOINTS).await?, before, "undo gives back the design before the joint edit");
    redo(page).await?;
    assert_eq!(eval(page, JOINTS).await?, edited, "redo gives back the edited design");
    assert_eq!(eval(page, "window.linkwright.store.result.which").await?, Value::Null);
    Ok(())
}

/// Outlines drawn with the polygon tool that cannot be a body are refused when closed (Enter), with
/// what is wrong and what to do in the status line, and no shape is added: two corners, three on one
/// line, a sliver a pixel thick, a bow tie. The corners stay: one more off the line, and it is drawn.
async fn outlines_refused(page: &Page) -> Result<()> {
    click(page, "[data-tool=polygon]").await?;
    click(page, "[data-kind-choice=fixed]").await?;
    // Off the grid, so that a corner lands a pixel from the line.
    let snap = eval(page, "document.getElementById('opt-snap').checked").await? == Value::Bool(true);
    if snap {
        click(page, "#opt-snap").await?;
    }
    let origin = eval(
        page,
        "(() => { const r = document.getElementById('canvas').getBoundingClientRect(); return [r.left, r.top]; })()",
    )
    .await?;
    let at = |(x, y): (f64, f64)| (origin[0].as_f64().unwrap_or(0.0) + x, origin[1].as_f64().unwrap_or(0.0) + y);
    let count = "window.linkwright.store.scene.fixed_bodies.length";
    let before = eval(page, count).await?;
    let hint = "window.linkwright.store.ui.hint";
    // What is drawn, its corners (pixels in the canvas) and what the status line says.
    let outlines = [
        (
            "two corners",
            vec![(200.0, 500.0), (300.0, 500.0)],
            "A body needs at least three corners that are not on one line",
        ),
        ("three on one line", vec![(200.0, 300.0), (300.0, 300.0), (400.0, 300.0)], "these are on one line"),
        ("a sliver", vec![(500.0, 500.0), (700.0, 501.0), (900.0, 500.0)], "these are almost on one line"),
        ("a bow tie", vec![(500.0, 200.0), (700.0, 300.0), (700.0, 200.0), (500.0, 300.0)], "crosses itself"),
    ];
    for (what, corners, says) in outlines {
        eval(page, "(window.linkwright.store.ui.hint = '') || true").await?;
        for corner in corners {
            tap(page, at(corner)).await?;
        }
        press_enter(page).await?;
        assert_eq!(eval(page, count).await?, before, "{what} was drawn");
        let told = eval(page, hint).await?;
        assert!(told.as_str().is_some_and(|h| h.contains(says)), "{what}: the status line says {told}");
        press(page, "Escape", "Escape", 27, "").await?;
    }
    for corner in [(200.0, 300.0), (300.0, 300.0), (400.0, 300.0)] {
        tap(page, at(corner)).await?;
    }
    press_enter(page).await?;
    tap(page, at((300.0, 200.0))).await?;
    press_enter(page).await?;
    assert_eq!(eval(page, count).await?.as_u64(), before.as_u64().map(|n| n + 1), "the triangle is drawn");
    undo(page).await?;
    if snap {
        click(page, "#opt-snap").await?;
    }
    click(page, "[data-tool=select]").await
}

/// Every label on the drawing shown (how far each pose is missed, the links' lengths, the ground
/// pivots' places) and whether any two of them overlap.
const LABELS: &str = "(() => { const all = [...document.querySelectorAll('#canvas .pose-miss, #canvas .dimension')]; \
    const shown = all.filter((t) => t.checkVisibility()).map((t) => [t.textContent, t.getBoundingClientRect(), t.classList.contains('pose-miss')]); \
    const over = []; for (let i = 0; i < shown.length; i++) for (let j = i + 1; j < shown.length; j++) { \
      const [a, b] = [shown[i][1], shown[j][1]]; \
      if (a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom) over.push(`${shown[i][0]} / ${shown[j][0]}`); } \
    return {all: all.length, shown: shown.length, misses: shown.filter((s) => s[2]).length, over}; })()";

/// The folding roof designed: at its first pose, halfway and at its last, no two labels on the
/// drawing overlap, and most of them are shown.
async fn labels_apart(page: &Page) -> Result<()> {
    open_example(page, "k3_folding_roof").await?;
    design_quickly(page).await?;
    let scrub = eval(page, "(() => { const r = document.getElementById('scrub').getBoundingClientRect(); return [r.left + r.width / 2, r.top + r.height / 2]; })()")
        .await?;
    let middle = (scrub[0].as_f64().ok_or("scrub")?, scrub[1].as_f64().ok_or("scrub")?);
    tap(page, middle).await?;
    for (place, key_name, code, key_code) in
        [("halfway", "", "", 0), ("at the end", "End", "End", 35), ("at the start", "Home", "Home", 36)]
    {
        if !key_name.is_empty() {
            key(page, key_name, code, key_code, 0).await?;
        }
        settle(page).await?;
        let labels = eval(page, LABELS).await?;
        assert_eq!(labels["over"], serde_json::json!([]), "labels overlap {place}: {labels}");
        let (all, shown) = (labels["all"].as_u64().unwrap_or(0), labels["shown"].as_u64().unwrap_or(0));
        assert!(all > 0 && 2 * shown > all && labels["misses"].as_u64() > Some(0), "{place}: {labels}");
    }
    Ok(())
}

/// The wall bed (its bed and wall named so), designed as a printed model: the springs suggested hook
/// on the bed and the wall by those names, not the engine's; the parts made with hooks say on which
/// part each spring bracket is mounted, in the parts list, the springs and the steps.
async fn springs_named(page: &Page) -> Result<()> {
    open_example(page, "k1_wall_bed_full_size").await?;
    design_quickly(page).await?;
    click(page, "[data-tab=result]").await?;
    click(page, "[data-action=springs]").await?;
    until(page, "window.linkwright.store.result.balance != null", Duration::from_secs(60)).await?;
    settle(page).await?;
    let words = eval(page, "document.querySelector('#tab-result ul.springs')?.textContent ?? ''").await?;
    let words = words.as_str().unwrap_or_default();
    assert!(words.contains("the moving body “bed”") && !words.contains("body1"), "{words}");

    let hooks = "document.getElementById('fab-springs')";
    if eval(page, &format!("{hooks}.checked")).await? != Value::Bool(true) {
        click(page, "#fab-springs").await?;
    }
    click(page, "#btn-fabricate").await?;
    until(
        page,
        "window.linkwright.results.fab.job === null && window.linkwright.results.fab.made !== null",
        Duration::from_secs(120),
    )
    .await?;
    settle(page).await?;
    let told = eval(
        page,
        "(() => { const a = window.linkwright.results.fab.made.answer; \
         const brackets = a.report.parts.filter((p) => p.role === 'spring_bracket').map((p) => p.name); \
         const listed = brackets.map((b) => document.querySelector(`#tab-result a[data-file=\"parts/${b}.stl\"]`)?.closest('li')?.textContent ?? ''); \
         const hooks = [...document.querySelectorAll('#tab-result [data-hooks]')].map((e) => e.textContent).join(' '); \
         const steps = [...document.querySelectorAll('#tab-result ol.steps li')].map((e) => e.textContent); \
         return {brackets, listed, hooks, steps: brackets.map((b) => steps.filter((s) => s.includes(`: ${b}`)))}; })()",
    )
    .await?;
    let brackets: Vec<&str> = told["brackets"].as_array().ok_or("brackets")?.iter().filter_map(Value::as_str).collect();
    assert!(!brackets.is_empty(), "the wall bed's springs stand on brackets: {told}");
    let hooks = told["hooks"].as_str().unwrap_or_default();
    for (k, bracket) in brackets.iter().enumerate() {
        let listed = told["listed"][k].as_str().unwrap_or_default();
        let mounts = ["the moving body “bed”", "the fixed body “wall”", "the fixed body “floor”"];
        assert!(mounts.iter().any(|m| listed.contains(&format!("mounted on {m}"))), "{listed}");
        assert!(hooks.contains(&format!("{bracket} (a bracket mounted on the ")), "{bracket}: {hooks}");
        for step in told["steps"][k].as_array().ok_or("steps")? {
            assert!(step.as_str().is_some_and(|s| s.contains(&format!("{bracket}, mounted on the "))), "{step}");
        }
    }
    assert!(!hooks.contains("body1"), "{hooks}");
    Ok(())
}

/// The motion exported as a WebM video has every frame the app draws (60, one travel), one every
/// 50 ms: read back element by element (EBML), its blocks and their times.
async fn motion_video_frames(page: &Page, downloads: &Path) -> Result<()> {
    click(page, "#tab-result [data-export=webm]").await?;
    let file = wait_for_file(downloads, ".motion.webm", Duration::from_secs(60)).await?;
    until(page, "window.linkwright.store.ui.hint.startsWith('Saved the motion')", Duration::from_secs(10)).await?;
    let times = webm_frame_times(&std::fs::read(&file)?).ok_or("a WebM file that reads")?;
    let every: Vec<u64> = (0..60).map(|i| i * 50).collect();
    assert_eq!(times, every, "the video's frames and their times (ms)");
    Ok(())
}

/// The time of each frame (SimpleBlock or Block) of a WebM file in milliseconds, in file order: its
/// cluster's time plus its own. Reads the EBML elements (IDs and sizes as variable-length integers;
/// a size of all ones is unknown, running to the end of the parent) and walks into the segment, its
/// clusters and block groups.
fn webm_frame_times(bytes: &[u8]) -> Option<Vec<u64>> {
    const SEGMENT: u64 = 0x1853_8067;
    const CLUSTER: u64 = 0x1F43_B675;
    const BLOCK_GROUP: u64 = 0xA0;
    const TIMECODE: u64 = 0xE7;
    const SIMPLE_BLOCK: u64 = 0xA3;
    const BLOCK: u64 = 0xA1;
    /// A variable-length integer at `at`: its value (with its length marker for an ID) and length.
    fn vint(bytes: &[u8], at: usize, id: bool) -> Option<(u64, usize)> {
        let first = *bytes.get(at)?;
        let len = first.leading_zeros() as usize + 1;
        if len > 8 {
            return None;
        }
        let mut value = if id { u64::from(first) } else { u64::from(first) & (0xFF >> len) };
        for k in 1..len {
            value = (value << 8) | u64::from(*bytes.get(at + k)?);
        }
        Some((value, len))
    }
    fn walk(bytes: &[u8], mut at: usize, end: usize, cluster: &mut u64, out: &mut Vec<u64>) -> Option<()> {
        while at < end {
            let (id, id_len) = vint(bytes, at, true)?;
            let (size, size_len) = vint(bytes, at + id_len, false)?;
            let data = at + id_len + size_len;
            let unknown = size == (1u64 << (7 * size_len)) - 1;
            let stop = if unknown { end } else { (data + usize::try_from(size).ok()?).min(end) };
            match id {
                SEGMENT | CLUSTER | BLOCK_GROUP => walk(bytes, data, stop, cluster, out)?,
                TIMECODE => *cluster = bytes.get(data..stop)?.iter().fold(0, |v, &b| (v << 8) | u64::from(b)),
                SIMPLE_BLOCK | BLOCK => {
                    let (_, track_len) = vint(bytes, data, false)?;
                    let relative =
                        i16::from_be_bytes([*bytes.get(data + track_len)?, *bytes.get(data + track_len + 1)?]);
                    out.push(cluster.checked_add_signed(i64::from(relative))?);
                }
                _ => {}
            }
            at = stop;
        }
        Some(())
    }
    let mut out = Vec::new();
    walk(bytes, 0, bytes.len(), &mut 0, &mut out)?;
    Some(out)
}

/// A pose typed far beyond what the engine takes (x 5,000,000): the reason the design is refused is
/// told in the screen's words, not the file's (no `[x_mm, y_mm, angle_deg]`, no `1e6`).
async fn pose_in_screen_words(page: &Page) -> Result<()> {
    click(page, "[data-tab=object]").await?;
    click(page, "li.row:has([data-key=moving-name-0])").await?;
    type_into(page, "[data-key=pose-0-1-x]", "5000000").await?;
    assert_eq!(eval(page, "window.linkwright.store.scene.moving_bodies[0].poses[1][0]").await?.as_f64(), Some(5e6));
    eval(page, "document.activeElement.blur() || true").await?;
    click(page, "#btn-design").await?;
    until(page, &format!("!({DESIGNING}) && window.linkwright.results.error !== null"), Duration::from_secs(20))
        .await?;
    settle(page).await?;
    let told = eval(page, "document.querySelector('#tab-result .callout.error')?.textContent ?? ''").await?;
    let told = told.as_str().unwrap_or_default();
    assert!(told.contains("pose 2 is at x 5000000, y "), "{told}");
    for file_word in ["x_mm", "angle_deg", "1e6", "["] {
        assert!(!told.contains(file_word), "{file_word} in {told}");
    }
    undo(page).await
}

/// At full size a body's mass field shows what it weighs in its material when left empty: that
/// number is shown whole, beside the field's arrows (the two-body wall bed, whose bodies have no
/// mass of their own).
async fn masses_fit(page: &Page) -> Result<()> {
    open_example(page, "k2_wall_bed").await?;
    click(page, "[data-tab=settings]").await?;
    click(page, "[data-key=build-full]").await?;
    design_quickly(page).await?;
    click(page, "[data-tab=result]").await?;
    until(page, "document.querySelectorAll('#tab-result table.masses input').length === 2", Duration::from_secs(20))
        .await?;
    // The text's width and the field's inner width less its arrows (about 15 pixels).
    let fits = "[...document.querySelectorAll('#tab-result table.masses input')].map((i) => { \
                const g = document.createElement('canvas').getContext('2d'), s = getComputedStyle(i); g.font = s.font; \
                const room = i.clientWidth - parseFloat(s.paddingLeft) - parseFloat(s.paddingRight) - 16; \
                return {placeholder: i.placeholder, text: Math.ceil(g.measureText(i.placeholder).width), room, \
                        scrolls: i.scrollWidth > i.clientWidth}; })";
    let fields = eval(page, fits).await?;
    for field in fields.as_array().ok_or("mass fields")? {
        assert!(field["placeholder"].as_str().is_some_and(|p| !p.is_empty()), "{field}");
        assert!(
            field["text"].as_f64() <= field["room"].as_f64() && field["scrolls"] == false,
            "the mass is cut: {field}"
        );
    }
    Ok(())
}
