"""Web-app page at /lab: `rotarydryer.app.page_lab.render`."""

from rotarydryer.app import page_lab

page_lab.render()
