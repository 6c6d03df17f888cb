"""The dependency rules of docs/design/index.md section 2: import-linter contracts and import checks."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
ROOT_PACKAGES = ("world", "match", "agents", "scenarios")
PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
CONTRACT_NAMES = {c["id"]: c["name"] for c in PYPROJECT["tool"]["importlinter"]["contracts"]}

LINT_IMPORTS = (
    "import sys; from importlinter.cli import lint_imports_command; sys.exit(lint_imports_command())"
)


def _lint_imports(cwd: Path) -> subprocess.CompletedProcess[str]:
    """Run lint-imports on the tree at ``cwd`` with this interpreter."""
    env = {**os.environ, "COLUMNS": "400"}
    return subprocess.run(
        [sys.executable, "-c", LINT_IMPORTS, "--no-cache", "--no-logo"],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )


def _loaded_modules_after(code: str) -> set[str]:
    """Names in ``sys.modules`` after running ``code`` in a fresh interpreter in the repo."""
    script = f"{code}\nimport sys\nprint('\\n'.join(sys.modules))"
    result = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr
    return set(result.stdout.split())


def test_contracts_are_kept() -> None:
    result = _lint_imports(REPO)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output
    assert f"Contracts: {len(CONTRACT_NAMES)} kept, 0 broken." in output, output


def test_contracts_cover_the_design_rules() -> None:
    assert set(CONTRACT_NAMES) >= {
        "world-standalone",
        "match-below-agents",
        "agents-see-only-public-facts",
        "public-facts-pure",
        "scenarios-common-below",
        "scenarios-concerns-independent",
        "scenarios-cli-on-top",
        "behavior-layers",
        "behavior-below-team",
    }


def _copy_tree(destination: Path) -> None:
    for package in ROOT_PACKAGES:
        shutil.copytree(REPO / package, destination / package, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(REPO / "pyproject.toml", destination)
    # Stand-ins for modules the cases import, where they do not exist yet.
    for stub in ("match/protocol.py", "match/env.py", "world/camera_model.py"):
        if not (destination / stub).exists():
            (destination / stub).write_text('"""Stand-in."""\n', encoding="utf-8")
    (destination / "world/_simulated.py").write_text("import pybullet\n", encoding="utf-8")


VIOLATIONS = {
    "world imports match": ("world-standalone", {"world/_bad.py": "import match\n"}),
    "world imports agents": ("world-standalone", {"world/_bad.py": "from agents import _bad\n"}),
    "match imports agents": ("match-below-agents", {"match/_bad.py": "import agents\n"}),
    "match imports scenarios": ("match-below-agents", {"match/_bad.py": "def f():\n    import scenarios\n"}),
    "agent imports pybullet": ("agents-see-only-public-facts", {"agents/_bad.py": "import pybullet as pb\n"}),
    "agent imports the env": ("agents-see-only-public-facts", {"agents/_bad.py": "from match import env\n"}),
    "agent imports world": ("agents-see-only-public-facts", {"agents/_bad.py": "import world\n"}),
    "agent imports scenarios": ("agents-see-only-public-facts", {"agents/_bad.py": "import scenarios\n"}),
    "nested agent imports the simulation": (
        "agents-see-only-public-facts",
        {"agents/_sub/__init__.py": "", "agents/_sub/_bad.py": "from world._simulated import pybullet\n"},
    ),
    "a skill imports a tactic": (
        "behavior-layers", {"agents/behavior/skills/_bad.py": "from agents.behavior.tactics import aim\n"},
    ),
    "a tactic imports a built-in policy": (
        "behavior-layers", {"agents/behavior/tactics/_bad.py": "import agents.behavior.policies.scripted\n"},
    ),
    "a shared tactic imports the team agent": (
        "behavior-below-team", {"agents/behavior/tactics/_bad.py": "from agents.team import params\n"},
    ),
    "field pulls in pybullet": ("public-facts-pure", {"world/field.py": "from world import _simulated\n"}),
    "scenarios.common imports a concern": (
        "scenarios-common-below",
        {"scenarios/common/_bad.py": "from scenarios.localization import samples\n"},
    ),
    "perception imports localization": (
        "scenarios-concerns-independent",
        {"scenarios/perception/_bad.py": "from scenarios.localization.samples import LocalizationSample\n"},
    ),
    "a tool imports perception": (
        "scenarios-concerns-independent",
        {"scenarios/tools/_bad.py": "def f():\n    import scenarios.perception.scoring\n"},
    ),
}


@pytest.mark.parametrize("case", list(VIOLATIONS))
def test_contracts_catch_violations(case: str, tmp_path: Path) -> None:
    contract_id, files = VIOLATIONS[case]
    _copy_tree(tmp_path)
    for relative, text in files.items():
        path = tmp_path / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        previous = path.read_text(encoding="utf-8") if path.exists() else ""
        path.write_text(previous + text, encoding="utf-8")
    result = _lint_imports(tmp_path)
    output = result.stdout + result.stderr
    assert result.returncode != 0, output
    assert f"{CONTRACT_NAMES[contract_id]} BROKEN" in output, output
    assert f"{len(CONTRACT_NAMES) - 1} kept, 1 broken." in output, output


def test_contracts_allow_the_public_facts(tmp_path: Path) -> None:
    _copy_tree(tmp_path)
    (tmp_path / "agents/_good.py").write_text(
        "from match import protocol\nfrom match.protocol import __doc__\n"
        "from world.field import FIELD\nimport world.camera_model\nimport numpy\n",
        encoding="utf-8",
    )
    result = _lint_imports(tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr


def test_field_does_not_import_pybullet() -> None:
    loaded = _loaded_modules_after("import world.field")
    assert "world.field" in loaded
    assert "pybullet" not in loaded


def test_agents_do_not_import_pybullet() -> None:
    """Importing every agent module, however indirectly, never loads pybullet."""
    code = (
        "import importlib, pkgutil, agents\n"
        "for info in pkgutil.walk_packages(agents.__path__, 'agents.'):\n"
        "    importlib.import_module(info.name)\n"
    )
    assert "pybullet" not in _loaded_modules_after(code)


def test_every_package_is_installed() -> None:
    """Each package on disk is listed in ``[tool.setuptools] packages`` (and nothing else is)."""
    on_disk = {
        ".".join(init.parent.relative_to(REPO).parts)
        for root in ROOT_PACKAGES
        for init in (REPO / root).rglob("__init__.py")
    }
    assert set(PYPROJECT["tool"]["setuptools"]["packages"]) == on_disk
