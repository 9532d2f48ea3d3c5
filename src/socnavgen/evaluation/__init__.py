"""Evaluation harness: the SocRATES paper's Tables I-III measured on any model."""
