from conftest import paths_reply, run_replay, scenario_reply, tree_reply, write_script


def test_smoke(tmp_path, mini_location):
    script = write_script(tmp_path / "s.yaml", {"scenario": [scenario_reply()], "paths": [paths_reply()],
                                                "behaviors": {"human1": [tree_reply()], "human2": [tree_reply()]}})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    if isinstance(run, Exception):
        raise run
    print(run.paths, run.behaviors["human1"])
