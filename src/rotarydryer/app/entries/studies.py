"""Web-app page at /studies: `rotarydryer.app.page_studies.render`."""

from rotarydryer.app import page_studies

page_studies.render()
