"""Web-app page at /transport: `rotarydryer.app.page_transport.render`."""

from rotarydryer.app import page_transport

page_transport.render()
