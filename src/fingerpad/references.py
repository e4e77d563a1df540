"""The publications behind fingerpad's methods: one registry, cited by every output.

Each method declares the publications it rests on by their keys here (a model class's
``REFERENCES``, :func:`fingerpad.contact.solver.solver_references`, ...); a job gathers the keys
of the methods its run used and writes them with its results: ``references`` in the JSON
outputs, the CF ``references`` attribute of the NetCDF files and Zarr stores, a list in the
analysis report. ``fingerpad cite`` prints how to cite the package and the thesis it implements.

The keys a run lists follow from its inputs (the models a study names, the options given), never
from what happened to run in this process (a unit cell read from the cache cites the solver
that made it): the same inputs list the same references on any machine.

A DOI is given only where it was checked against the publication or a published citation of it;
the others are cited by journal, volume and pages.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from ._version import __version__

__all__ = ["PACKAGE", "REFERENCES", "THESIS", "Reference", "bibtex", "citation", "keys_of", "metadata",
           "netcdf_attribute", "ordered"]


@dataclass(frozen=True)
class Reference:
    """One publication (or the package itself).

    Attributes
    ----------
    key
        The registry key (also the BibTeX key).
    kind
        ``article``, ``book``, ``phdthesis``, ``software`` or ``manual`` (the package's own
        documentation, for a derivation made there).
    authors
        ``"Family, G. N."`` each.
    title, year
        As published.
    venue
        Journal, publisher or school.
    volume, number, pages, doi, isbn, url
        Where known; ``""`` otherwise.
    used_for
        What fingerpad takes from it, in a few words.
    """

    key: str
    kind: str
    authors: tuple[str, ...]
    title: str
    year: int
    venue: str
    used_for: str
    volume: str = ""
    number: str = ""
    pages: str = ""
    doi: str = ""
    isbn: str = ""
    url: str = ""


#: The key of the thesis whose model fingerpad implements (the preferred reference for the model).
THESIS = "sergachev2021"
#: The key of the package itself.
PACKAGE = "fingerpad"

_ALL = (
    Reference(THESIS, "phdthesis", ("Sergachev, D. A.",), "Surface engineering of tactile friction", 2021,
              "University of Twente, Enschede",
              "the multiscale contact and friction model: Eqs. 2.1-2.7 (friction, pad area), 3.1-3.14 "
              "(micro scale, coupling)",
              doi="10.3990/1.9789036551786", isbn="978-90-365-5178-6"),
    Reference(PACKAGE, "software", ("The fingerpad developers",),
              "fingerpad: multiscale finger-pad contact and tactile friction on textured surfaces", 2026,
              "", "the implementation (version of the run)", volume=""),
    Reference("sergachev2022", "article", ("Sergachev, D.", "Matthews, D.", "van der Heide, E."),
              "Design of bidirectional frictional behaviour for tactile contact using ellipsoidal asperity "
              "micro-textures", 2022, "Friction", "directional friction of compliant ellipsoidal asperities",
              volume="10", number="5", pages="762-771"),
    Reference("johnson1985", "book", ("Johnson, K. L.",), "Contact Mechanics", 1985, "Cambridge University Press",
              "Hertz contact of the pad and of single asperities; the contact modulus",
              doi="10.1017/CBO9781139171731"),
    Reference("dzidek2017", "article",
              ("Dzidek, B. M.", "Adams, M. J.", "Andrews, J. W.", "Zhang, Z.", "Johnson, S. A."),
              "Contact mechanics of the human finger pad under compressive loads", 2017,
              "Journal of the Royal Society Interface", "the strain-stiffened pad modulus, Eqs. 2.6-2.7",
              volume="14", number="127", pages="20160935"),
    Reference("greenwood1958", "article", ("Greenwood, J. A.", "Tabor, D."),
              "The friction of hard sliders on lubricated rubber: the importance of deformation losses", 1958,
              "Proceedings of the Physical Society", "the hysteresis friction term, Eq. 2.4",
              volume="71", pages="989-1001"),
    Reference("westergaard1939", "article", ("Westergaard, H. M.",), "Bearing pressures and cracks", 1939,
              "Journal of Applied Mechanics", "contact of a 1-D sinusoid (sinusoidal ridges)",
              volume="6", pages="A49-A53"),
    Reference("polonsky1999", "article", ("Polonsky, I. A.", "Keer, L. M."),
              "A numerical method for solving rough contact problems based on the multi-level multi-summation "
              "and conjugate gradient techniques", 1999, "Wear",
              "the constrained conjugate gradient of the contact solver",
              volume="231", number="2", pages="206-219", doi="10.1016/S0043-1648(99)00113-1"),
    Reference("love1929", "article", ("Love, A. E. H.",),
              "The stress produced in a semi-infinite solid by pressure on part of the boundary", 1929,
              "Philosophical Transactions of the Royal Society A",
              "the pixel-integrated Boussinesq kernel of non-periodic maps",
              volume="228", pages="377-420", doi="10.1098/rsta.1929.0009"),
    Reference("johnson1971", "article", ("Johnson, K. L.", "Kendall, K.", "Roberts, A. D."),
              "Surface energy and the contact of elastic solids", 1971, "Proceedings of the Royal Society A",
              "the adhesive (JKR) pad and pull-off force, Eqs. 3.15-3.17, and the JKR limit of adhesive asperities",
              volume="324", number="1558", pages="301-313"),
    Reference("maugis1992", "article", ("Maugis, D.",),
              "Adhesion of spheres: the JKR-DMT transition using a Dugdale model", 1992,
              "Journal of Colloid and Interface Science", "the Maugis-Dugdale interaction law and transition parameter",
              volume="150", number="1", pages="243-269"),
    Reference("rey2017", "article", ("Rey, V.", "Anciaux, G.", "Molinari, J.-F."),
              "Normal adhesive contact on rough surfaces: efficient algorithm for FFT-based BEM resolution", 2017,
              "Computational Mechanics", "adhesive contact with the gap as the unknown of the FFT-BEM",
              volume="60", number="1", pages="69-81"),
    Reference("fingerpad-layered", "manual", ("The fingerpad developers",),
              "fingerpad documentation, docs/model.md section 6.4: the compliance of an elastic layer on an "
              "elastic half-space or a rigid base", 2026, "",
              "the layered skin's Fourier-space compliance (a derivation with Papkovich-Neuber potentials)"),
    Reference("sobol2001", "article", ("Sobol', I. M.",),
              "Global sensitivity indices for nonlinear mathematical models and their Monte Carlo estimates", 2001,
              "Mathematics and Computers in Simulation", "variance-based sensitivity indices",
              volume="55", number="1-3", pages="271-280", doi="10.1016/S0378-4754(00)00270-6"),
    Reference("saltelli2010", "article",
              ("Saltelli, A.", "Annoni, P.", "Azzini, I.", "Campolongo, F.", "Ratto, M.", "Tarantola, S."),
              "Variance based sensitivity analysis of model output. Design and estimator for the total "
              "sensitivity index", 2010, "Computer Physics Communications",
              "the pick-and-freeze design and the first-order estimator",
              volume="181", number="2", pages="259-270", doi="10.1016/j.cpc.2009.09.018"),
    Reference("jansen1999", "article", ("Jansen, M. J. W.",), "Analysis of variance designs for model output", 1999,
              "Computer Physics Communications", "the total-index estimator",
              volume="117", number="1-2", pages="35-43", doi="10.1016/S0010-4655(98)00154-4"),
    Reference("kruskal1958", "article", ("Kruskal, W. H.",), "Ordinal measures of association", 1958,
              "Journal of the American Statistical Association",
              "rank to normal correlation of a population's correlated parameters",
              volume="53", number="284", pages="814-861", doi="10.1080/01621459.1958.10501481"),
    Reference("davies1987", "article", ("Davies, R. B.",),
              "Hypothesis testing when a nuisance parameter is present only under the alternative", 1987,
              "Biometrika", "the test of a transition whose load is searched for",
              volume="74", number="1", pages="33-43", doi="10.1093/biomet/74.1.33"),
    Reference("besag1991", "article", ("Besag, J.", "Clifford, P."), "Sequential Monte Carlo p-values", 1991,
              "Biometrika", "the early stop of the simulated transition test",
              volume="78", number="2", pages="301-304", doi="10.1093/biomet/78.2.301"),
    Reference("gueorguiev2017", "article",
              ("Gueorguiev, D.", "Vezzoli, E.", "Mouraux, A.", "Lemaire-Semail, B.", "Thonnard, J.-L."),
              "The tactile perception of transient changes in friction", 2017,
              "Journal of the Royal Society Interface", "the Weber fraction of friction, 0.11 (the default W)",
              volume="14", number="137", pages="20170641", doi="10.1098/rsif.2017.0641"),
    Reference("sahli2020", "article",
              ("Sahli, R.", "Prot, A.", "Wang, A.", "Müser, M. H.", "Piovarči, M.", "Didyk, P.", "Bennewitz, R."),
              "Tactile perception of randomly rough surfaces", 2020, "Scientific Reports",
              "the friction difference noticed on rough surfaces (0.035 at mu 0.34-0.45)",
              volume="10", pages="15800", doi="10.1038/s41598-020-72890-y"),
    Reference("fehlberg2022", "article",
              ("Fehlberg, M.", "Kim, K.-S.", "Drewing, K.", "Hensel, R.", "Bennewitz, R."),
              "Perception of friction in tactile exploration of micro-structured rubber samples", 2022,
              "Haptics: Science, Technology, Applications (EuroHaptics 2022), Lecture Notes in Computer Science",
              "the relative friction difference noticed on textured samples (about 0.2)",
              volume="13235", pages="21-29", doi="10.1007/978-3-031-06249-0_3"),
    Reference("delhaye2012", "article", ("Delhaye, B.", "Hayward, V.", "Lefèvre, P.", "Thonnard, J.-L."),
              "Texture-induced vibrations in the forearm during tactile exploration", 2012,
              "Frontiers in Behavioral Neuroscience", "the vibration's fundamental f = v / lambda",
              volume="6", pages="37", doi="10.3389/fnbeh.2012.00037"),
    Reference("bolanowski1988", "article",
              ("Bolanowski, S. J.", "Gescheider, G. A.", "Verrillo, R. T.", "Checkosky, C. M."),
              "Four channels mediate the mechanical aspects of touch", 1988,
              "Journal of the Acoustical Society of America", "the receptor channels by vibration frequency",
              volume="84", number="5", pages="1680-1694"),
    Reference("verrillo1963", "article", ("Verrillo, R. T.",), "Effect of contactor area on the vibrotactile threshold",
              1963, "Journal of the Acoustical Society of America",
              "the shape of the vibrotactile detection threshold (flat below 40 Hz, minimum near 250 Hz)",
              volume="35", pages="1962-1966"),
    Reference("hollins2007", "article", ("Hollins, M.", "Bensmaïa, S. J."), "The coding of roughness", 2007,
              "Canadian Journal of Experimental Psychology",
              "the duplex theory of roughness: spatial above ~0.2 mm, vibrotactile below",
              volume="61", number="3", pages="184-195"),
    Reference("drewing2016", "article", ("Drewing, K.",),
              "Low-amplitude textures explored with the bare finger: roughness judgments follow an inverted "
              "U-shaped function of texture period modified by texture type", 2016,
              "Haptics: Perception, Devices, Control, and Applications (EuroHaptics 2016), Lecture Notes in Computer "
              "Science", "roughness peaking where the skin reaches the texture's floor",
              volume="9775", doi="10.1007/978-3-319-42324-1_21"),
    Reference("drewing2018", "article", ("Drewing, K.",),
              "Judged roughness as a function of groove frequency and groove width in 3D-printed gratings", 2018,
              "Haptics: Science, Technology, and Applications (EuroHaptics 2018), Lecture Notes in Computer Science",
              "roughness of low-amplitude gratings against groove width and frequency",
              volume="10893", doi="10.1007/978-3-319-93445-7_23"),
    Reference("iglewicz1993", "book", ("Iglewicz, B.", "Hoaglin, D. C."), "How to Detect and Handle Outliers", 1993,
              "ASQC Quality Press", "the robust z-score of the stroke outlier flag"),
)

#: Every reference by key, in the order outputs list them.
REFERENCES: dict[str, Reference] = {ref.key: ref for ref in _ALL}


def ordered(keys: Iterable[str]) -> list[Reference]:
    """The references of ``keys``, each once, in the registry's order (the package and the thesis
    first).

    Raises
    ------
    KeyError
        A key that is not in :data:`REFERENCES` (a method declaring a publication the registry
        lacks: a bug, caught by the tests).
    """
    wanted = set(keys)
    unknown = sorted(wanted - set(REFERENCES))
    if unknown:
        raise KeyError(f"unknown reference keys: {', '.join(unknown)}")
    return [ref for key, ref in REFERENCES.items() if key in wanted]


def keys_of(*sources: object) -> tuple[str, ...]:
    """The keys that ``sources`` declare: a key (str), an iterable of keys, or an object (a model
    class or instance, a module) with ``REFERENCES``; ``None`` is skipped. The package and the
    thesis always come first: every run of fingerpad uses the thesis' model."""
    found: list[str] = [PACKAGE, THESIS]
    for source in sources:
        if source is None:
            continue
        if isinstance(source, str):
            found.append(source)
        elif hasattr(source, "REFERENCES"):  # a model (class or instance) or a module declaring them
            found.extend(source.REFERENCES)
        else:
            found.extend(source)  # type: ignore[call-overload]
    return tuple(ref.key for ref in ordered(found))


def _authors_text(authors: tuple[str, ...]) -> str:
    if len(authors) == 1:
        return authors[0]
    return ", ".join(authors[:-1]) + " and " + authors[-1]


def citation(ref: Reference | str) -> str:
    """One line: authors (year), title, venue volume(number):pages, DOI."""
    ref = REFERENCES[ref] if isinstance(ref, str) else ref
    if ref.key == PACKAGE:
        return f"{_authors_text(ref.authors)} ({ref.year}). {ref.title}, version {__version__}. MIT licence."
    where = ref.venue
    if ref.kind == "phdthesis":
        where = f"PhD thesis, {ref.venue}"
    if ref.volume:
        where += f" {ref.volume}" + (f"({ref.number})" if ref.number else "")
    if ref.pages:
        where += f":{ref.pages}"
    parts = [f"{_authors_text(ref.authors)} ({ref.year}). {ref.title}."]
    if where:
        parts.append(f"{where}.")
    if ref.doi:
        parts.append(f"doi:{ref.doi}")
    return " ".join(parts)


def metadata(keys: Iterable[str]) -> list[dict[str, str]]:
    """The ``references`` entry of a JSON output: per reference its key, one-line citation, DOI
    (``""`` where none is given) and what fingerpad uses it for."""
    return [{"key": ref.key, "citation": citation(ref), "doi": ref.doi, "used_for": ref.used_for}
            for ref in ordered(keys)]


def netcdf_attribute(keys: Iterable[str]) -> str:
    """The CF ``references`` global attribute: one citation per line."""
    return "\n".join(citation(ref) for ref in ordered(keys))


#: BibTeX's entry types (plain BibTeX has no software type: misc, with the version as a note).
_BIBTEX_TYPES = {"article": "article", "book": "book", "phdthesis": "phdthesis", "software": "misc",
                 "manual": "manual"}


def _bibtex_entry(ref: Reference) -> str:
    # a person as "Family, G."; a body's name braced, so that BibTeX does not split it into names
    authors = " and ".join(a if ", " in a else "{" + a + "}" for a in ref.authors)
    fields: list[tuple[str, str]] = [("author", authors), ("title", "{" + ref.title + "}"), ("year", str(ref.year))]
    if ref.kind == "article":
        fields.append(("journal", ref.venue))
    elif ref.kind == "phdthesis":
        fields.append(("school", ref.venue))
    elif ref.venue:
        fields.append(("publisher", ref.venue))
    fields += [(name, value) for name, value in (("volume", ref.volume), ("number", ref.number),
                                                 ("pages", ref.pages.replace("-", "--")), ("doi", ref.doi),
                                                 ("isbn", ref.isbn), ("url", ref.url)) if value]
    if ref.key == PACKAGE:
        fields += [("version", __version__), ("note", f"Version {__version__}, MIT licence")]
    body = ",\n".join(f"  {name} = {{{value}}}" for name, value in fields)
    return f"@{_BIBTEX_TYPES[ref.kind]}{{{ref.key},\n{body}\n}}"


def bibtex(keys: Iterable[str]) -> str:
    """BibTeX entries of ``keys`` (registry order), separated by blank lines."""
    return "\n\n".join(_bibtex_entry(ref) for ref in ordered(keys)) + "\n"
