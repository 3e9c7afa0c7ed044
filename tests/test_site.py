"""The documentation site: its reference covers the public API, its generated
pages cover the schemas, its internal links resolve, and it works in a browser
with no network (math rendered, figures present, search working).

The built site (``make docs``, which ``make test`` runs first) is read from
``docs/_build/html``; where it is not built the tests that need it are skipped,
and under CI they fail (:mod:`browsing`).
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterator
from html.parser import HTMLParser
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlsplit

import pytest

from browsing import chromium, missing, open_offline

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SITE = DOCS / "_build" / "html"
sys.path.insert(0, str(DOCS / "_ext"))

import tumble_docs  # noqa: E402


@pytest.fixture(scope="module")
def site() -> Path:
    if not (SITE / "index.html").is_file():
        missing("the documentation site is not built (make docs)")
    return SITE


# ------------------------------------------------------------------ the reference
def _autosummary_names(page: Path) -> tuple[str, list[str]]:
    """The current module of a reference page and the names its autosummary
    tables list."""
    text = page.read_text(encoding="utf-8")
    module = re.search(r"^\.\. currentmodule:: (\S+)", text, re.MULTILINE)
    assert module is not None, f"{page.name} names no current module"
    names = re.findall(r"^   ([A-Za-z_][A-Za-z0-9_]*)$", text, re.MULTILINE)
    return module.group(1), names


def test_every_public_name_is_listed_in_the_reference_sources() -> None:
    listed = set()
    for page in sorted((DOCS / "reference").glob("*.rst")):
        if page.stem in {"index", "scenario-keys", "cli"}:
            continue
        module, names = _autosummary_names(page)
        listed |= {f"{module}.{name}" for name in names}
        # tumble's own page also documents __version__ and points to its modules.
    modules = {f"tumble.{name}" for name in tumble_docs.PUBLIC_MODULES}
    expected = set(tumble_docs.public_names()) - modules - {"tumble.__version__"}
    assert expected - listed == set(), "public names missing from docs/reference"
    assert listed - expected == set(), "docs/reference lists names that are not public"
    # Every public module has its page, and tumble's __all__ names no other module.
    assert {p.stem for p in (DOCS / "reference").glob("*.rst")} >= set(tumble_docs.PUBLIC_MODULES)
    import tumble

    submodules = {n for n in tumble.__all__ if type(getattr(tumble, n)).__name__ == "module"}
    assert submodules == set(tumble_docs.PUBLIC_MODULES)


def test_every_public_name_has_its_entry_in_the_built_site(site: Path) -> None:
    from sphinx.util.inventory import InventoryFile

    with (site / "objects.inv").open("rb") as stream:
        inventory = InventoryFile.load(stream, "", lambda base, target: target)
    documented = {name for kind, entries in inventory.items() if kind.startswith("py:")
                  for name in entries}  # fmt: skip
    missing_names = set(tumble_docs.public_names()) - documented
    assert missing_names == set()


# ------------------------------------------------------------------ generated pages
def _model_keys(model: Any, seen: set[type]) -> Iterator[str]:
    """The keys of a pydantic model and of the models it holds, recursively."""
    import typing

    if model in seen:
        return
    seen.add(model)
    for name, field in model.model_fields.items():
        yield name
        stack = [field.annotation]
        while stack:
            kind = stack.pop()
            if isinstance(kind, type) and hasattr(kind, "model_fields"):
                yield from _model_keys(kind, seen)
            stack.extend(typing.get_args(kind))


def test_the_scenario_keys_page_names_every_key_the_parsers_accept() -> None:
    from tumble.scenario.schema import scenario_schema
    from tumble.sweep.schema import SweepFile
    from tumble.torques import TORQUES

    page = tumble_docs.scenario_keys()
    keys = set(_model_keys(scenario_schema(), set())) | set(_model_keys(SweepFile, set()))
    keys |= {p.name for model in TORQUES.values() if model.in_files for p in model.parameters}
    # "values" holds a torque's parameters once validated; files write them directly.
    keys -= {"values"}
    forms = ("``{}``", "``[{}]``", "``[[{}]]``", "``[{}.")  # a key, a table, an array of tables
    absent = sorted(key for key in keys if not any(f.format(key) in page for f in forms))
    assert absent == []
    for table in ("[scenario]", "[simulation]", "[[internal]]", "[[torques]]", "[vary.NAME]"):
        assert f"``{table}``" in page


def test_the_command_line_page_shows_every_command_and_option() -> None:
    import typer

    from tumble.cli.app import app

    page = tumble_docs.command_line()
    group = typer.main.get_command(app)
    context = group.make_context("tumble", [], resilient_parsing=True)
    for name in group.list_commands(context):
        assert f"``tumble {name}``" in page
        command = group.get_command(context, name)
        for parameter in command.params:
            for option in parameter.opts:
                if option.startswith("--"):
                    assert option in page, f"tumble {name} {option}"


def test_the_architecture_page_describes_every_module_of_the_layers_contract() -> None:
    # The page's diagram is drawn from pyproject.toml when the site is built; its
    # descriptions, keyed by module, must cover the contract and nothing else.
    text, problems = tumble_docs.architecture_layers()
    assert problems == []
    _, layers = tumble_docs.contract_layers()
    labels = [line.split("  ")[0] for line in text.splitlines() if not line.startswith(" ")]
    assert labels == layers
    # The closed forms sit below the integrators that sample them.
    assert labels.index("integrators") < labels.index("torques | theory") < labels.index("body")


def test_the_layers_diagram_names_what_the_page_and_the_contract_disagree_on() -> None:
    layers = ["cli", "theory | analysis", "core"]
    descriptions = {"cli": "commands", "theory": "closed forms", "core": "kernels", "old": "x"}
    text, problems = tumble_docs.layers_diagram(layers, descriptions)
    assert problems == [
        "The layers contract names tumble.analysis, which the page does not describe: "
        "add a line `analysis: what it holds`.",
        "The page describes tumble.old, which the layers contract does not name: remove its "
        "line or add it to the contract.",
    ]
    assert text.splitlines()[1] == "theory | analysis".ljust(28) + "closed forms;"
    parsed = tumble_docs.layer_descriptions(["cli: typer", "  commands", "", "core: kernels"])
    assert parsed == {"cli": "typer commands", "core": "kernels"}


def test_bars_of_norms_are_escaped_outside_literals_and_math() -> None:
    lines = [
        "|L| and ``x |y|`` and :math:`|z|` and `|w|`",
        "``atol + rtol ·",
        "   |value|`` then |ω|",
        ".. math::",
        "",
        "   |q| = 1",
        "after |p|",
    ]
    tumble_docs.escape_bars(None, "function", "f", None, None, lines)
    assert lines == [
        r"\|L\| and ``x |y|`` and :math:`|z|` and `|w|`",
        "``atol + rtol ·",
        r"   |value|`` then \|ω\|",
        ".. math::",
        "",
        "   |q| = 1",
        r"after \|p\|",
    ]


def test_references_to_internals_read_as_text_and_to_public_names_must_resolve() -> None:
    from types import SimpleNamespace

    app = SimpleNamespace(config=SimpleNamespace(tumble_public_names=tumble_docs.public_names()))

    def resolve(target: str) -> Any:
        node = {"refdomain": "py", "reftarget": target}
        return tumble_docs.quiet_internal_references(app, None, node, "text")

    assert resolve("tumble.core.splitting") == "text"
    assert resolve("tumble.sweep.plan.METRICS") == "text"  # a module of a public module
    assert resolve("numpy.ndarray") == "text"
    assert resolve("tumble.simulate") is None  # documented: a miss is a real error
    assert resolve("tumble.MassProperties.principal") is None
    assert resolve("tumble.theory.flip_period") is None


# ------------------------------------------------------------------ links
class _Anchors(HTMLParser):
    """The ids a page defines and the addresses it refers to."""

    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.references: list[str] = []
        self.loads: list[str] = []  # what the browser fetches: scripts, styles, images

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = dict(attrs)
        for key in ("id", "name"):
            if values.get(key):
                self.ids.add(str(values[key]))
        for key in ("href", "src"):
            if values.get(key):
                self.references.append(str(values[key]))
        fetched = tag in {"script", "img", "iframe", "source", "video", "audio"} or (
            tag == "link" and values.get("rel") in {"stylesheet", "preload", "icon"}
        )
        address = values.get("src") or values.get("href")
        if fetched and address:
            self.loads.append(address)


def _pages(site: Path) -> list[Path]:
    """The site's pages (``_static`` holds the theme's templates, not pages)."""
    return sorted(p for p in site.rglob("*.html") if "_static" not in p.relative_to(site).parts)


def _parse(page: Path, pages: dict[Path, _Anchors]) -> _Anchors:
    if page not in pages:
        parser = _Anchors()
        parser.feed(page.read_text(encoding="utf-8", errors="replace"))
        pages[page] = parser
    return pages[page]


def test_every_internal_link_and_anchor_of_the_site_resolves(site: Path) -> None:
    pages: dict[Path, _Anchors] = {}
    broken = []
    count = 0
    for page in _pages(site):
        for reference in _parse(page, pages).references:
            address = urlsplit(reference)
            if address.scheme or address.netloc or reference.startswith("mailto:"):
                continue  # the network: not part of the offline site
            count += 1
            target = (page.parent / unquote(address.path)).resolve() if address.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(site)}: {reference}")
            elif (
                address.fragment
                and target.suffix == ".html"
                and unquote(address.fragment) not in _parse(target, pages).ids
            ):
                broken.append(f"{page.relative_to(site)}: {reference} (no such anchor)")
    assert count > 1000  # the check saw the site, not an empty folder
    assert broken == []


def test_the_site_loads_nothing_from_the_network(site: Path) -> None:
    """No page loads a script, style, font or image from elsewhere (links to other
    sites, which a reader may follow, are allowed)."""
    pages: dict[Path, _Anchors] = {}
    remote = [
        f"{page.relative_to(site)}: {address}"
        for page in _pages(site)
        for address in _parse(page, pages).loads
        if urlsplit(address).scheme in {"http", "https"} or address.startswith("//")
    ]
    assert sum(len(p.loads) for p in pages.values()) > 100  # it saw the pages' scripts
    assert remote == []


# ------------------------------------------------------------------ the browser
@pytest.fixture(scope="module")
def browser(site: Path) -> Iterator[Any]:
    with chromium() as launched:
        yield launched


def _first(folder: Path, pattern: str) -> Path:
    found = sorted(folder.glob(pattern))
    assert found, f"no {pattern} in {folder}"
    return found[0]


def test_the_landing_page_opens_offline(browser: Any, site: Path) -> None:
    page, errors = open_offline(browser, (site / "index.html").as_uri())
    page.wait_for_load_state("load")
    assert "tumble" in page.title()
    assert page.locator("a[href*='auto_tutorials']").count() > 0
    assert errors == []


def test_a_tutorial_renders_its_math_and_figures_offline(browser: Any, site: Path) -> None:
    tutorial = _first(site / "auto_tutorials", "plot_*.html")
    page, errors = open_offline(browser, tutorial.as_uri())
    page.wait_for_function("window.MathJax && MathJax.startup && MathJax.startup.promise")
    page.evaluate("MathJax.startup.promise")
    assert page.locator("mjx-container").count() > 0
    assert page.locator("mjx-merror").count() == 0
    _figures_are_drawn(page)
    assert errors == []


def test_a_gallery_page_shows_its_figures_and_downloads_offline(browser: Any, site: Path) -> None:
    example = _first(site / "auto_examples", "plot_*.html")
    page, errors = open_offline(browser, example.as_uri())
    page.wait_for_load_state("load")
    _figures_are_drawn(page)
    for suffix in (".py", ".ipynb"):
        link = page.locator(f"a.download[href$='{suffix}']")
        assert link.count() > 0
        href = link.first.get_attribute("href")
        assert (example.parent / unquote(href)).is_file()
    assert errors == []


def _figures_are_drawn(page: Any) -> None:
    images = page.locator("img.sphx-glr-single-img, img.sphx-glr-multi-img")
    assert images.count() > 0
    sizes = images.evaluate_all("els => els.map(e => e.complete ? e.naturalWidth : 0)")
    assert all(width > 0 for width in sizes), sizes


def test_the_search_page_finds_gyrocompass_offline(browser: Any, site: Path) -> None:
    page, errors = open_offline(browser, (site / "search.html").as_uri() + "?q=gyrocompass")
    page.wait_for_selector("#search-results ul.search li a", timeout=20_000)
    hits = page.locator("#search-results ul.search li a").all_inner_texts()
    assert any("yrocompass" in hit for hit in hits), hits
    assert errors == []


def test_a_build_without_the_mathjax_wheel_says_what_to_install(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    from types import SimpleNamespace

    monkeypatch.setattr(tumble_docs.importlib.util, "find_spec", lambda name: None)
    app = SimpleNamespace(builder=SimpleNamespace(format="html"), outdir=str(tmp_path))
    with pytest.raises(RuntimeError, match=r"^sphinx-mathjax-offline is not installed: pip "):
        tumble_docs.copy_mathjax(app, None)
