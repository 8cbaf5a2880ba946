"""Web-app page at /control: `rotarydryer.app.page_control.render`."""

from rotarydryer.app import page_control

page_control.render()
