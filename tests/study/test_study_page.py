"""The study's page in real browsers (headless Chromium): two participants rate every result, the methods hidden; resuming."""

import httpx
import pytest
from browser import chromium, chromium_pages
from serving import Server
from studies import METHOD_NAME, METHODS, key, results_csv

from exprclone.study.folder import read_key, read_study

pytestmark = pytest.mark.slow  # servers, browsers, clusters or videos: pytest -m 'not slow' leaves these out

#: where the page keeps the participant's id.
STORAGE_KEY = "exprclone-study-participant"
#: what each participant clicks: set index to method to score (participant A with the mouse, B with the keyboard).
SCORES = {
    "A": {0: {"global": 1, "elastic+eri": 3, "e+md": 5}, 1: {"global": 2, "elastic+eri": 4, "e+md": 5}},
    "B": {0: {"global": 2, "elastic+eri": 3, "e+md": 4}, 1: {"global": 1, "elastic+eri": 5, "e+md": 3}},
}
#: milliseconds the page may take to show a step.
TIMEOUT = 20_000


@pytest.fixture()
def served(study_folder):
    running = Server(str(study_folder), command=("study", "serve"))
    yield running.url
    running.stop()


def orders(url: str, participant: str) -> list[list[str]]:
    sets = httpx.get(f"{url}/api/participants/{participant}").json()["sets"]
    return [[i["id"] for i in s["items"]] for s in sets]


def two_participants_with_different_orders(url: str, tries: int = 20) -> tuple[str, str]:
    """A participant, and another who sees some set's results in another order (the page's shuffle, not the test's)."""
    first = httpx.post(f"{url}/api/participants").json()["id"]
    for _ in range(tries):
        other = httpx.post(f"{url}/api/participants").json()["id"]
        if orders(url, other) != orders(url, first):
            return first, other
    raise AssertionError(f"{tries + 1} participants all see the same orders: the results are not shuffled")


def shown_set(page, k: int, count: int) -> list[str]:
    """The results of the set on screen, in the page's order, once its images have loaded; checks what each shows."""
    page.wait_for_function(f"document.querySelector('#set-title').textContent === 'Set {k + 1} of {count}'", timeout=TIMEOUT)
    page.wait_for_function("[...document.images].every((i) => i.complete && i.naturalWidth > 0)", timeout=TIMEOUT)
    items = page.eval_on_selector_all("#items [data-item]", "(boxes) => boxes.map((b) => b.dataset.item)")
    for item in items:
        assert item in page.get_attribute(f"[data-item='{item}'] img", "src")
        assert page.eval_on_selector_all(f"[data-item='{item}'] input[type=radio]", "(r) => r.map((i) => i.value)") == list("12345")
    assert not METHOD_NAME.search(page.content())
    return items


def rate_with_the_mouse(page, items: list[str], scores: dict, methods: dict) -> None:
    page.click("#submit")  # nothing rated yet: the page says so and stays
    assert "Rate every result" in page.text_content("#error") and page.is_visible("#set")
    for item in items:
        page.check(f"[data-item='{item}'] input[value='{scores[methods[item][1]]}']")
    page.click("#submit")


def rate_with_the_keyboard(page, items: list[str], scores: dict, methods: dict) -> None:
    for item in items:  # the set's title has the focus: Tab reaches each result's scale in turn
        page.keyboard.press("Tab")
        assert page.evaluate("document.activeElement.closest('[data-item]').dataset.item") == item
        page.keyboard.press("Space")
        for _ in range(scores[methods[item][1]] - 1):
            page.keyboard.press("ArrowRight")
    page.keyboard.press("Tab")
    assert page.evaluate("document.activeElement.id") == "submit"
    page.keyboard.press("Enter")


def take_part(page, url: str, participant: str, who: str, methods: dict, count: int) -> list[list[str]]:
    """One participant's whole study on ``page``: age and gender, then each set rated; the orders they saw."""
    page.context.add_init_script(f"localStorage.setItem('{STORAGE_KEY}', '{participant}')")
    page.goto(url)
    page.wait_for_selector("#about:not([hidden])", timeout=TIMEOUT)
    if who == "A":
        page.fill("#age", "34")
        page.select_option("#gender", "female")
        page.click("#begin")
    else:  # the keyboard only, the questions left unanswered
        for _ in range(3):
            page.keyboard.press("Tab")
        assert page.evaluate("document.activeElement.id") == "begin"
        page.keyboard.press("Enter")
    seen = []
    for k in range(count):
        seen.append(shown_set(page, k, count))
        (rate_with_the_mouse if who == "A" else rate_with_the_keyboard)(page, seen[-1], SCORES[who][k], methods)
    page.wait_for_selector("#done:not([hidden])", timeout=TIMEOUT)
    return seen


def test_two_participants_rate_every_result_in_their_own_order_and_the_methods_stay_hidden(served, study_folder, tmp_path):
    study, methods = read_study(study_folder), key(study_folder)
    count = len(study.sets)
    participants = dict(zip("AB", two_participants_with_different_orders(served)))
    with chromium_pages(2) as pages:
        responses = []
        for page in pages:
            page.on("requestfinished", lambda request: responses.append(request))
        seen = {who: take_part(page, served, participants[who], who, methods, count) for who, page in zip("AB", pages)}
        texts = [r.url for r in responses] + [r.response().text() for r in responses if "image" not in r.response().headers["content-type"]]
        assert any("/api/participants/" in t for t in texts) and any("use strict" in t for t in texts)  # the scripts and JSON are in
        leaks = [t[:80] for t in texts if METHOD_NAME.search(t)]
        assert not leaks
    for k, s in enumerate(study.sets):
        assert sorted(seen["A"][k]) == sorted(seen["B"][k]) == sorted(s.items)  # every result of each set
    assert seen["A"] != seen["B"]  # in their own orders
    assert seen == {who: orders(served, participants[who]) for who in "AB"}
    rows = results_csv(study_folder, tmp_path / "t.csv")
    names = read_key(study_folder).names
    assert [(r["set"], r["method"]) for r in rows] == [(name, m) for name in names for m in METHODS]
    for row in rows:
        k = names.index(row["set"])
        clicked = [SCORES[who][k][row["method"]] for who in "AB"]
        assert int(row["n"]) == 2 and float(row["mean"]) == sum(clicked) / 2, row


def test_a_participant_who_comes_back_resumes_with_the_same_order(served, study_folder):
    with chromium() as page:
        page.goto(served)
        page.click("#begin")
        participant = page.evaluate(f"localStorage.getItem('{STORAGE_KEY}')")
        first = shown_set(page, 0, 2)
        for item in first:
            page.check(f"[data-item='{item}'] input[value='4']")
        page.click("#submit")
        second = shown_set(page, 1, 2)
        page.reload()
        assert shown_set(page, 1, 2) == second and page.is_hidden("#about")
        assert page.evaluate(f"localStorage.getItem('{STORAGE_KEY}')") == participant
    state = httpx.get(f"{served}/api/participants/{participant}").json()
    assert state["ratings"] == {"0": dict.fromkeys(first, 4)} and state["about"] == {"age": None, "gender": None}
