"""End-to-end jobs built from the layers below: part modes and part studies, the arm
accuracy study, model comparisons, contact applications (loaded circle, chatter), arm
pictures, and the demo that composes them.  Each job is a function returning a frozen
result with its own writer; the CLI only calls them.
"""
