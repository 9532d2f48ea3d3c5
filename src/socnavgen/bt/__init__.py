"""Behavior trees: the node library (single source of truth), safe XML parsing, validation."""
