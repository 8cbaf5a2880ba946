"""Web-app page at /geometry: `rotarydryer.app.page_geometry.render`."""

from rotarydryer.app import page_geometry

page_geometry.render()
