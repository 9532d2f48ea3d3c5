"""Headless 2D simulator: social-force pedestrians driven by the generated behavior trees."""
