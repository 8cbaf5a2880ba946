"""Published data sets (CSV, first line = source); read them with rotarydryer.published."""
