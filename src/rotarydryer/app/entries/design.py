"""Web-app page at /design: `rotarydryer.app.page_design.render`."""

from rotarydryer.app import page_design

page_design.render()
