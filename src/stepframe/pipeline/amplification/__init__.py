"""The site amplification job: a site's model, its moving-resonance amplification and its report.

:mod:`.site` (the site model from parameters, a record or a features table), :mod:`.amplify`
(amplification for one oscillator and the curve over f0), :mod:`.study` (``stochastic
amplify``), :mod:`.report` (the HTML report), :mod:`.report_options` (its inputs; light) and
:mod:`.stage` (the workflow's ``site``, ``amplification`` and ``amplification_report`` stages).
"""
