"""Entry scripts of the web app's pages, one file per page (``st.navigation`` runs the file of the
page whose address the browser asked for: /geometry, /transport ...; the default page at /).

Each file only calls the ``render()`` of its page module (`rotarydryer.app.streamlit_app.PAGES`);
being files (not callables), the pages can be opened in Streamlit's AppTest harness with
``AppTest.switch_page("entries/<url path>.py")``.
"""
