"""Web-app page (placeholder until built): see streamlit_app.PAGES."""

import streamlit as st


def render():
    st.title("studies")
    st.info("This page is being built.")
