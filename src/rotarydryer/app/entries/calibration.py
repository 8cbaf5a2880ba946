"""Web-app page at /calibration: `rotarydryer.app.page_calibration.render`."""

from rotarydryer.app import page_calibration

page_calibration.render()
