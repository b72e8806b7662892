"""README's "What it does" shows what `rankloci locus puma560 --numeric --quiet`
prints, the time aside."""

import re
from pathlib import Path

from rankloci.cli import main

README = Path(__file__).resolve().parents[2] / "README.md"
COMMAND = "rankloci locus puma560 --numeric --quiet"


def _without_time(text: str) -> str:
    return re.sub(r", [0-9.]+ s$", ", ... s", text.strip("\n"), count=1, flags=re.M)


def readme_excerpt() -> str:
    """The output under the ``$ COMMAND`` line of README's text block."""
    block = README.read_text(encoding="utf-8").split(f"```text\n$ {COMMAND}\n", 1)[1]
    return block.split("\n```", 1)[0]


def test_readme_shows_what_the_command_prints(capsys):
    assert main(COMMAND.split()[1:]) == 0
    printed = capsys.readouterr().out
    assert _without_time(readme_excerpt()) == _without_time(printed)
