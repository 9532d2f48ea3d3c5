"""socnavgen: social navigation scenarios for HuNavSim, generated from text and a map."""

__version__ = "0.1.0"
