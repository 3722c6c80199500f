"""A stream that fails leaves no folder its --report created (the report's folder is made before the stream
starts, so the frames can be written as they are sent); a folder that existed stays."""
import os

from metamaterial_wb.hardware import link, streamer

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _failing_stream(monkeypatch, report):
    def boom(self, *args, **kwargs):
        raise link.LinkError("board went away")
    monkeypatch.setattr(streamer.Streamer, "run", boom)
    from metamaterial_wb.cli import main
    try:
        return main(["stream", os.path.join(ROOT, "examples", "fish.json"), "--dry-run", "--seconds", "1",
                     "--report", str(report)])
    except SystemExit as exc:
        return exc.code


def test_a_failed_stream_removes_the_report_folders_it_made(tmp_path, monkeypatch, capsys):
    rc = _failing_stream(monkeypatch, tmp_path / "new" / "a" / "b" / "r.json")
    assert rc == 2 and "board went away" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


def test_a_failed_stream_keeps_a_folder_that_existed(tmp_path, monkeypatch, capsys):
    (tmp_path / "mine").mkdir()
    rc = _failing_stream(monkeypatch, tmp_path / "mine" / "new" / "r.json")
    assert rc == 2
    assert os.listdir(tmp_path) == ["mine"] and os.listdir(tmp_path / "mine") == []

