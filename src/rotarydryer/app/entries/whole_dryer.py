"""Web-app page at /whole_dryer: `rotarydryer.app.page_dryer.render`."""

from rotarydryer.app import page_dryer

page_dryer.render()
