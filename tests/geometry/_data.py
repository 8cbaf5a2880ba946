"""Published data shipped in rotarydryer/data."""

from rotarydryer.published import read_published_csv as read_csv  # noqa: F401
