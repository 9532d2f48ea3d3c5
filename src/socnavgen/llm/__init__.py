"""The only way the pipeline talks to models: `make_llm(spec)` returns an `LLM`."""
