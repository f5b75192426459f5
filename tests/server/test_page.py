"""The web page in a real browser (headless Chromium): a photo and an expression, the sliders, the result large with its
full-size view; the paper's choices under "Advanced"; a photo with no face says so as soon as it is chosen; a phone's
narrow window."""

import httpx
import numpy as np
import pytest
from browser import chromium
from conftest import paper_terms
from PIL import Image
from serving import Server

from exprclone import data as samples
from exprclone.options import ADVANCED

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: milliseconds the page may take for a clone (the first one starts a worker's caches).
CLONE_TIMEOUT = 60_000


@pytest.fixture(scope="module")
def server():
    running = Server("--workers", "1")
    yield running.url
    running.stop()


@pytest.fixture(scope="module")
def page(server):
    with chromium() as page:
        page.goto(server)
        yield page


def advanced(page):
    """The "Advanced" fold open: the paper's choices (method, lambda_k, warps, landmarker, compare)."""
    page.evaluate("document.querySelector('#advanced').open = true")


def set_photos(page, target):
    """The source's two photos (126's) and the target's: the expression from two photos."""
    page.check("#source-photos")
    page.set_input_files("input[type=file][name=source_neutral]", str(samples.path("126")))
    page.set_input_files("input[type=file][name=source_expression]", str(samples.path("126", "smile")))
    page.set_input_files("input[type=file][name=target_neutral]", str(target))


def test_clone_shows_the_result_at_the_target_size(page):
    set_photos(page, samples.path("003"))
    page.click("#clone")
    page.wait_for_function("document.querySelector('img#result').naturalWidth > 0", timeout=CLONE_TIMEOUT)
    size = page.evaluate("[document.querySelector('img#result').naturalWidth, document.querySelector('img#result').naturalHeight]")
    assert size == [1350, 1350]
    assert page.is_hidden("#error")
    assert "e+md" in page.text_content("#result-caption") and "λk" in page.text_content("#result-caption")
    assert page.get_attribute("#download-png", "href").startswith("data:image/png;base64,")
    page.click("#toggle")  # before/after: the target's own photo
    assert page.get_attribute("img#result", "src").startswith("blob:")


def test_swapped_source_photos_are_warned_of_beside_the_result(page):
    set_photos(page, samples.path("003"))
    page.set_input_files("input[type=file][name=source_neutral]", str(samples.path("126", "smile")))
    page.set_input_files("input[type=file][name=source_expression]", str(samples.path("126")))
    advanced(page)
    page.select_option("#method", "elastic")
    page.click("#clone")
    page.wait_for_function("document.querySelector('#busy').hidden", timeout=CLONE_TIMEOUT)
    assert page.is_hidden("#error") and page.is_visible("#result-box")
    assert page.text_content("#warning") == (
        "source neutral: looks more expressive than source_expression; are the source's two photos swapped?"
    )
    # beside the result: right above its image, seen with it (it sat 970 px above, off screen when the result was looked at)
    page.locator("img#result").scroll_into_view_if_needed()
    warning, result = (page.locator(s).bounding_box() for s in ("#warning", "img#result"))
    assert 0 <= result["y"] - (warning["y"] + warning["height"]) < 40, (warning, result)
    assert page.evaluate("document.querySelector('#warning').getBoundingClientRect().top >= 0")
    set_photos(page, samples.path("003"))  # the right order: the warning goes
    page.click("#clone")
    page.wait_for_function("document.querySelector('#busy').hidden", timeout=CLONE_TIMEOUT)
    assert page.is_hidden("#warning")
    page.select_option("#method", "e+md")


def test_landmarks_are_drawn_over_a_chosen_photo(page):
    page.set_input_files("input[type=file][name=target_neutral]", str(samples.path("003")))
    page.wait_for_function(
        """() => { const c = document.querySelector('[data-field=target_neutral] canvas');
                   const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
                   for (let i = 0; i < d.length; i += 4) if (d[i + 1] > 200 && d[i] < 60 && d[i + 3] > 0) return true; return false; }""",
        timeout=CLONE_TIMEOUT,
    )


def test_a_photo_without_a_face_is_named_in_the_error(page, tmp_path):
    blank = tmp_path / "blank.png"
    Image.fromarray(np.full((400, 400, 3), 128, np.uint8)).save(blank)
    set_photos(page, blank)
    page.wait_for_selector("[data-field=target_neutral] .problem", state="visible", timeout=CLONE_TIMEOUT)
    page.click("#clone")
    page.wait_for_function("document.querySelector('#busy').hidden", timeout=CLONE_TIMEOUT)  # the page is usable again
    assert page.is_visible("#error") and page.is_enabled("#clone")
    assert page.text_content("#error").startswith("target neutral: no face found")


#: what the zone says of each photo chosen, at once: no face, too small (a whole face at 60x60), not an image.
CHOSEN_PROBLEMS = {
    "blank.png": "no face found",
    "small.png": "too small to find a face in (60x60 pixels; at least 80 on each side needed)",
    "notes.txt": "not an image",
}


@pytest.mark.parametrize("name", CHOSEN_PROBLEMS)
def test_a_chosen_photo_says_what_is_wrong_with_it_before_clone(page, tmp_path, name):
    """As soon as a photo is chosen, its zone says what is wrong with it (the server looks at it at once), before
    Clone is pressed; Clone then says it again without sending the clone; a good photo chosen after it clears it."""
    path = tmp_path / name
    if name == "blank.png":
        Image.fromarray(np.full((400, 400, 3), 128, np.uint8)).save(path)
    elif name == "small.png":
        Image.open(samples.path("003")).resize((60, 60), Image.LANCZOS).save(path)
    else:
        path.write_text("not a photo")
    page.reload()
    sent = []
    page.on("request", lambda request: sent.append(request.url) if "/api/edits" in request.url else None)
    page.set_input_files("input[type=file][name=target_neutral]", str(path))
    said = "[data-field=target_neutral] .problem"
    page.wait_for_selector(said, state="visible", timeout=CLONE_TIMEOUT)
    assert CHOSEN_PROBLEMS[name] in page.text_content(said), page.text_content(said)
    assert page.is_hidden("#result-box")
    page.click("#clone")
    assert page.text_content("#error").startswith("target neutral: ") and CHOSEN_PROBLEMS[name] in page.text_content("#error")
    assert sent == []
    page.set_input_files("input[type=file][name=target_neutral]", str(samples.path("003")))
    page.wait_for_selector(said, state="hidden", timeout=CLONE_TIMEOUT)


def test_the_transfer_controls_reach_the_clone(page):
    set_photos(page, samples.path("003"))
    advanced(page)
    page.select_option("#global-warp", "rbf")
    page.select_option("#image-warp", "tps")
    page.fill("#strength", "0.5")
    page.fill("#strength-eyes", "0")
    page.uncheck("#retarget")
    page.select_option("#landmarker", "mesh")
    page.evaluate("document.querySelector('img#result').removeAttribute('src')")
    page.click("#clone")
    page.wait_for_function(
        "document.querySelector('#busy').hidden && document.querySelector('img#result').naturalWidth > 0", timeout=CLONE_TIMEOUT
    )
    caption = page.text_content("#result-caption")
    assert "global warp rbf" in caption and "tps" in caption and "strength 0.5" in caption and "eyes 0," in caption, caption
    assert "no retarget" in caption and "mesh landmarks" in caption, caption
    page.select_option("#landmarker", "dlib")
    page.click("#strengths-reset")
    page.check("#retarget")
    page.select_option("#global-warp", "")
    page.select_option("#image-warp", "mesh")


def opening_of(image) -> float:
    """The mouth's opening in a face of an image, its landmarks found afresh: the inner lips' area, in pixels (the
    opening over the squared mouth width would shrink as a strong smile widens the mouth)."""
    from exprclone.landmarks.backends import default_detector
    from exprclone.landmarks.layout import DLIB68
    from exprclone.mouth import measure

    points = default_detector().detect(image)
    return measure.opening(points, DLIB68) * measure.mouth_width(points, DLIB68) ** 2


#: what the result on screen was rendered with (the page's data-rendered), as a JavaScript expression.
RENDERED = "JSON.parse(document.querySelector('img#result').dataset.rendered || '{}')"


def test_dragging_the_mouth_slider_opens_the_mouth_step_by_step(page):
    """Ten steps of the mouse along the mouth's slider, from 0 to its top: ten new previews (512 pixels), the mouth
    opening more at each; letting go makes the full size; the keyboard moves the slider too."""
    import io

    page.reload()
    set_photos(page, samples.path("003"))
    page.click("#clone")
    page.wait_for_function("document.querySelector('img#result').dataset.rendered", timeout=CLONE_TIMEOUT)
    page.fill("#strength-mouth", "0")
    page.dispatch_event("#strength-mouth", "change")
    page.wait_for_function(f"{RENDERED}.strength_mouth === '0'", timeout=CLONE_TIMEOUT)
    box = page.locator("#strength-mouth").bounding_box()
    y, left, width = box["y"] + box["height"] / 2, box["x"], box["width"]
    page.mouse.move(left + 1, y)
    page.mouse.down()
    openings = []
    for step in range(1, 11):
        page.mouse.move(left + width * step / 10 - (1 if step == 10 else 0), y)
        value = page.input_value("#strength-mouth")
        page.wait_for_function(
            f"(r => r.size === 'preview' && r.strength_mouth === '{value}')({RENDERED})",
            timeout=CLONE_TIMEOUT,
        )
        shot = page.evaluate("fetch(document.querySelector('img#result').src).then(r => r.arrayBuffer()).then(b => [...new Uint8Array(b)])")
        image = np.asarray(Image.open(io.BytesIO(bytes(shot))).convert("RGB"))
        assert max(image.shape[:2]) == 512
        openings.append((float(value), opening_of(image)))
    page.mouse.up()
    values = [v for v, _ in openings]
    assert len(set(values)) == 10 and values == sorted(values) and values[-1] == 2.0, values
    assert np.all(np.diff([o for _, o in openings]) > 0), openings
    page.wait_for_function(f"{RENDERED}.size === 'full'", timeout=CLONE_TIMEOUT)
    assert page.evaluate("document.querySelector('img#result').naturalWidth") == 1350
    assert "mouth 2" in page.text_content("#result-caption")
    page.focus("#strength-mouth")
    page.keyboard.press("Home")  # the keyboard works the slider: to its least value
    page.wait_for_function(f"{RENDERED}.strength_mouth === '0'", timeout=CLONE_TIMEOUT)
    page.click("#strengths-reset")


def test_compare_draws_figure_19(page):
    set_photos(page, samples.path("003"))
    advanced(page)
    page.select_option("#figure", "19")
    page.evaluate("document.querySelector('#sheet').removeAttribute('src')")
    page.click("#compare")
    page.wait_for_function("document.querySelector('#sheet').naturalWidth > 0", timeout=CLONE_TIMEOUT)
    assert page.evaluate("document.querySelector('#sheet').naturalWidth") == 6 * 320
    assert "Figs. 19-21" in page.text_content("#sheet-caption")


def test_compare_draws_figure_17_whatever_global_warp_the_fold_holds(page):
    set_photos(page, samples.path("003"))
    advanced(page)
    page.select_option("#figure", "17")
    page.select_option("#global-warp", "rbf")  # Fig. 17 is drawn on Song et al.'s warp whatever the fold holds
    page.evaluate("document.querySelector('#sheet').removeAttribute('src')")
    page.click("#compare")
    page.wait_for_function("document.querySelector('#sheet').naturalWidth > 0", timeout=CLONE_TIMEOUT)
    assert page.evaluate("document.querySelector('#sheet').naturalWidth") == 7 * 320  # the server's Fig. 17 sheet
    assert "Fig. 17" in page.text_content("#sheet-caption") and page.is_hidden("#error")
    page.select_option("#global-warp", "")


def test_a_built_in_expression_needs_one_photo(page):
    page.reload()
    page.check("#source-builtin")
    assert page.is_hidden("[data-field=source_neutral]") and page.is_hidden("[data-field=source_expression]")
    page.wait_for_function("document.querySelectorAll('#expression option').length >= 2", timeout=CLONE_TIMEOUT)
    assert page.input_value("#expression") == "smile"  # offered first, though "angry" sorts before it
    page.set_input_files("input[type=file][name=target_neutral]", str(samples.path("001")))
    page.click("#clone")
    page.wait_for_function(
        "document.querySelector('#busy').hidden && document.querySelector('img#result').naturalWidth > 0", timeout=CLONE_TIMEOUT
    )
    assert page.is_hidden("#error"), page.text_content("#error")
    assert "expression smile" in page.text_content("#result-caption")
    page.check("#source-photos")
    assert page.is_visible("[data-field=source_neutral]") and page.is_disabled("#expression")


def test_the_faces_of_a_group_photo_are_outlined_and_a_click_leaves_one_out(page, tmp_path):
    """Three faces outlined on the target's preview, each with a checkbox; a click on a face unticks it, and the clone
    leaves that face as it is."""
    from exprclone.evaluation.groups import make
    from exprclone.io.images import save_image

    image, _ = make(samples.london(), samples.PEOPLE, (110, 170, 250), (760, 800), seed=4)
    save_image(tmp_path / "group.png", image)
    page.reload()
    page.check("#source-builtin")
    page.wait_for_function("document.querySelectorAll('#expression option').length >= 2", timeout=CLONE_TIMEOUT)
    page.select_option("#expression", "smile")
    page.set_input_files("input[type=file][name=target_neutral]", str(tmp_path / "group.png"))
    page.wait_for_function("document.querySelectorAll('#faces input').length === 3", timeout=CLONE_TIMEOUT)
    assert page.is_visible("#faces") and page.is_checked("#face-2")
    found = page.evaluate("document.querySelector('[data-field=target_neutral]').faces")
    left, top, right, bottom = found["faces"][1]["box"]
    canvas = page.locator("[data-field=target_neutral] canvas")
    scale = canvas.bounding_box()["width"] / found["width"]
    canvas.click(position={"x": (left + right) / 2 * scale, "y": (top + bottom) / 2 * scale})
    assert not page.is_checked("#face-2") and page.is_checked("#face-1")
    page.click("#clone")
    page.wait_for_function(
        "document.querySelector('#busy').hidden && document.querySelector('img#result').naturalWidth > 0", timeout=CLONE_TIMEOUT
    )
    assert page.is_hidden("#error"), page.text_content("#error")
    assert "faces 1,3 of 3" in page.text_content("#result-caption")
    # each face cloned, a thumbnail that opens the full-size view on it (the faces were ~50 px on the page)
    page.wait_for_selector("#result-faces", state="visible")
    assert page.eval_on_selector_all("#result-faces button", "bs => bs.map(b => b.id)") == ["result-face-1", "result-face-3"]
    page.click("#result-face-3")
    page.wait_for_function("document.querySelector('#viewer').open")
    assert "face 3" in page.text_content("#viewer-title")
    shown = page.evaluate(
        """() => { const a = document.querySelector('#viewer .canvas'), i = document.querySelector('#viewer-image');
                   return [a.scrollLeft, a.scrollTop, a.clientWidth, a.clientHeight, i.naturalWidth, i.clientWidth]; }"""
    )
    left, top, right, bottom = found["faces"][2]["box"]
    x, y = (left + right) / 2 - shown[0], (top + bottom) / 2 - shown[1]  # the face's centre, in the view
    assert 0 < x < shown[2] and 0 < y < shown[3] and shown[4] == shown[5] == image.shape[1], shown
    page.click("#viewer-close")
    page.check("#face-2")  # the keyboard's way: its checkbox
    page.set_input_files("input[type=file][name=target_neutral]", str(samples.path("003")))
    page.wait_for_function("document.querySelector('#faces').hidden", timeout=CLONE_TIMEOUT)


def test_the_first_view_speaks_no_paper_term_outside_the_advanced_fold(page):
    """A person's first view: a photo, an expression, the sliders; the paper's words (lambda_k, DB, ERI, a global warp...)
    and its choices' controls only under "Advanced", closed, where each choice has its plain sentence."""
    page.reload()
    page.wait_for_selector("#strength")
    assert not page.evaluate("document.querySelector('#advanced').open")
    seen = page.evaluate("document.body.innerText")
    assert paper_terms(seen) == [], paper_terms(seen)
    assert "Your photo" in seen and "The expression" in seen and "Whole expression" in seen
    described = httpx.get(page.url.rstrip("/") + "/api/options").json()["options"]
    folded = [o["key"].replace("_", "-") for o in described if o["page"] and o["page"]["section"] in ADVANCED and "form" in o["surfaces"]]
    assert {"method", "lambda", "global-warp", "image-warp", "landmarker", "retarget"} <= set(folded)
    for key in folded:
        assert page.evaluate(f"!!document.querySelector('#advanced #{key}')"), key
        assert not page.is_visible(f"#{key}"), key
    for key in ("figure", "compare", "show-landmarks", "global_landmarks"):
        assert page.evaluate(f"!!document.querySelector('#advanced #{key}')") and not page.is_visible(f"#{key}"), key
    advanced(page)
    for option in (o for o in described if o["key"].replace("_", "-") in folded):
        words = page.text_content(f"p.option:has(#{option['key'].replace('_', '-')}) small")
        assert page.is_visible(f"#{option['key'].replace('_', '-')}") and words == option["page"]["sentence"], option["key"]


def test_the_full_size_view_opens_and_toggles_before_and_after(page):
    """The result large on the page, and at its own pixels in the full-size view (a button, or a click on it), where
    before/after toggles too; Escape closes it."""
    page.reload()
    page.select_option("#expression", "smile")
    page.set_input_files("input[type=file][name=target_neutral]", str(samples.path("003")))
    page.click("#clone")
    page.wait_for_function("document.querySelector('img#result').naturalWidth > 0", timeout=CLONE_TIMEOUT)
    shown = page.locator("img#result").bounding_box()
    assert shown["width"] >= 700, shown  # large: twice the 365 px it had beside the photo before
    page.click("#full-size")
    page.wait_for_function("document.querySelector('#viewer').open && document.querySelector('#viewer-image').naturalWidth > 0")
    size = page.evaluate("(i => [i.naturalWidth, i.clientWidth, i.naturalHeight, i.clientHeight])(document.querySelector('#viewer-image'))")
    assert size == [1350, 1350, 1350, 1350], size
    assert page.get_attribute("#viewer-image", "src").startswith("data:image/png;base64,")
    page.click("#viewer-toggle")
    assert page.get_attribute("#viewer-image", "src").startswith("blob:") and page.text_content("#toggle") == "Show after"
    page.click("#viewer-toggle")
    page.keyboard.press("Escape")
    page.wait_for_function("!document.querySelector('#viewer').open")
    page.click("#result-open")  # the picture itself opens it too
    page.wait_for_function("document.querySelector('#viewer').open")
    page.click("#viewer-close")


def test_a_phone_sized_window_works(page):
    """A phone's window (390 x 844): nothing wider than the screen, the zones and the sliders stacked, a clone of the
    built-in smile within the width, its full-size view at its own pixels."""
    phone = page
    phone.set_viewport_size({"width": 390, "height": 844})
    try:
        phone.reload()
        phone.wait_for_selector("#strength")
        wide = "document.documentElement.scrollWidth <= window.innerWidth"
        assert phone.evaluate(wide), phone.evaluate("document.documentElement.scrollWidth")
        zone, sliders = (phone.locator(s).bounding_box() for s in ("[data-field=target_neutral]", "#strengths"))
        assert sliders["y"] > zone["y"] + zone["height"] and sliders["width"] > 300, (zone, sliders)
        assert phone.locator("#strength").bounding_box()["width"] > 150
        phone.select_option("#expression", "smile")
        phone.set_input_files("input[type=file][name=target_neutral]", str(samples.path("001")))
        phone.click("#clone")
        phone.wait_for_function("document.querySelector('img#result').naturalWidth > 0", timeout=CLONE_TIMEOUT)
        assert phone.is_hidden("#error"), phone.text_content("#error")
        result = phone.locator("img#result").bounding_box()
        assert 300 < result["width"] <= 390 and phone.evaluate(wide), result
        phone.click("#full-size")
        phone.wait_for_function("document.querySelector('#viewer').open")
        assert phone.evaluate("document.querySelector('#viewer-image').clientWidth") == 1350
        close = phone.locator("#viewer-close").bounding_box()
        assert close["x"] + close["width"] <= 390 and close["y"] >= 0, close  # the way out is on the screen
        phone.click("#viewer-close")
    finally:
        phone.set_viewport_size({"width": 1280, "height": 900})
