"""Every SSP 1.0 feature we apply, each on a system whose right answer is known by hand.

The Gain test FMU (tests/fmus/gain.py) computes y_real = k*u_real,
y_int = u_int + 1, y_bool = not u_bool, so the value that reaches a downstream
input is easy to predict. The SSD files are written out in full here, by hand,
so that the reader is tested against independently written XML.
"""
from __future__ import annotations

import shutil
import zipfile
from pathlib import Path

import pytest

from openemss.orchestrator.errors import SystemStructureError
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system

HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n'
        '<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" '
        'xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" '
        'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" '
        'xmlns:ssm="http://ssp-standard.org/SSP1/SystemStructureParameterMapping" '
        'xmlns:ssb="http://ssp-standard.org/SSP1/SystemStructureSignalDictionary" version="1.0" name="T">\n')

UNITS = """<ssd:Units>
  <ssc:Unit name="K"><ssc:BaseUnit K="1"/></ssc:Unit>
  <ssc:Unit name="degC"><ssc:BaseUnit K="1" offset="273.15"/></ssc:Unit>
  <ssc:Unit name="degF"><ssc:BaseUnit K="1" factor="0.5555555555555556" offset="255.3722222222222"/></ssc:Unit>
  <ssc:Unit name="m"><ssc:BaseUnit m="1"/></ssc:Unit>
  <ssc:Unit name="ft"><ssc:BaseUnit m="1" factor="0.3048"/></ssc:Unit>
  <ssc:Unit name="m/s"><ssc:BaseUnit m="1" s="-1"/></ssc:Unit>
  <ssc:Unit name="kn"><ssc:BaseUnit m="1" s="-1" factor="0.5144444444444445"/></ssc:Unit>
</ssd:Units>"""


def gain(name: str, k: float = 1.0, u_real: float | None = None, units: tuple[str | None, str | None] = (None, None),
         u_int: int | None = None, u_bool: bool | None = None) -> str:
    """A Gain component with all six connectors; optional units on u_real / y_real and start values."""
    def unit(u: str | None) -> str:
        return f' unit="{u}"' if u else ""
    params = [f'<ssv:Parameter name="k"><ssv:Real value="{k}"/></ssv:Parameter>']
    if u_real is not None:
        params.append(f'<ssv:Parameter name="u_real"><ssv:Real value="{u_real}"/></ssv:Parameter>')
    if u_int is not None:
        params.append(f'<ssv:Parameter name="u_int"><ssv:Integer value="{u_int}"/></ssv:Parameter>')
    if u_bool is not None:
        params.append(f'<ssv:Parameter name="u_bool"><ssv:Boolean value="{str(u_bool).lower()}"/></ssv:Parameter>')
    return f"""<ssd:Component name="{name}" source="resources/Gain.fmu">
  <ssd:Connectors>
    <ssd:Connector name="u_real" kind="input"><ssc:Real{unit(units[0])}/></ssd:Connector>
    <ssd:Connector name="u_int" kind="input"><ssc:Integer/></ssd:Connector>
    <ssd:Connector name="u_bool" kind="input"><ssc:Boolean/></ssd:Connector>
    <ssd:Connector name="y_real" kind="output"><ssc:Real{unit(units[1])}/></ssd:Connector>
    <ssd:Connector name="y_int" kind="output"><ssc:Integer/></ssd:Connector>
    <ssd:Connector name="y_bool" kind="output"><ssc:Boolean/></ssd:Connector>
  </ssd:Connectors>
  <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
    <ssv:ParameterSet version="1.0" name="p"><ssv:Parameters>{''.join(params)}</ssv:Parameters></ssv:ParameterSet>
  </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
</ssd:Component>"""


def connection(start: str, end: str, inner: str = "", suppress: bool = False) -> str:
    se, sc = start.split(".", 1) if "." in start else ("", start)
    ee, ec = end.split(".", 1) if "." in end else ("", end)
    attrs = (f' startElement="{se}"' if se else "") + f' startConnector="{sc}"' + \
            (f' endElement="{ee}"' if ee else "") + f' endConnector="{ec}"' + \
            (' suppressUnitConversion="true"' if suppress else "")
    return f"<ssd:Connection{attrs}>{inner}</ssd:Connection>" if inner else f"<ssd:Connection{attrs}/>"


def system_xml(elements: str, connections: str, units: str = UNITS, extra: str = "", bindings: str = "",
               enumerations: str = "") -> str:
    conns = f"<ssd:Connections>{connections}</ssd:Connections>" if connections else ""
    return (HEAD + f'<ssd:System name="T">{bindings}<ssd:Elements>{elements}</ssd:Elements>'
            f'{conns}{extra}</ssd:System>{enumerations}{units}'
            '<ssd:DefaultExperiment startTime="0" stopTime="1"/></ssd:SystemStructureDescription>\n')


def make(folder: Path, fmu_dir: Path, xml: str, files: dict[str, str] | None = None) -> Path:
    (folder / "resources").mkdir(parents=True, exist_ok=True)
    shutil.copy2(fmu_dir / "Gain.fmu", folder / "resources" / "Gain.fmu")
    (folder / "SystemStructure.ssd").write_text(xml)
    for name, text in (files or {}).items():
        (folder / name).write_text(text)
    return folder


def final(folder: Path, *paths: str) -> dict[str, float]:
    """Run 0.2 s at 10 Hz (Jacobi) and return the last recorded value of each path."""
    ex = Execution(bind_system(load_system(folder)), rate_hz=10.0, record=list(paths))
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(0.2)
    out = rec.result()
    return {p: float(out[p][-1]) for p in paths}


# -- connections -----------------------------------------------------------------------------------
def test_linear_transformation_on_a_connection(tmp_path: Path, fmu_dir: Path) -> None:
    xml = system_xml(gain("a", k=1.0, u_real=2.0) + gain("b"),
                     connection("a.y_real", "b.u_real",
                                '<ssc:LinearTransformation factor="3.0" offset="1.0"/>'))
    assert final(make(tmp_path, fmu_dir, xml), "b.u_real")["b.u_real"] == pytest.approx(7.0)  # 3*2 + 1


@pytest.mark.parametrize("start_unit, end_unit, value, expected", [
    ("degC", "K", 20.0, 293.15),       # offset: a factor-only conversion gives 20
    ("K", "degC", 300.0, 26.85),       # the inverse: an offset with the wrong sign gives 573.15
    ("degF", "degC", 212.0, 100.0),    # factor and offset on both sides
    ("ft", "m", 1000.0, 304.8),
    ("kn", "m/s", 100.0, 51.44444444444445),
])
def test_unit_conversion_between_connected_connectors(tmp_path: Path, fmu_dir: Path, start_unit: str,
                                                      end_unit: str, value: float, expected: float) -> None:
    xml = system_xml(gain("a", k=1.0, u_real=value, units=(None, start_unit)) + gain("b", units=(end_unit, None)),
                     connection("a.y_real", "b.u_real"))
    assert final(make(tmp_path, fmu_dir, xml), "b.u_real")["b.u_real"] == pytest.approx(expected, rel=1e-12)


def test_transformation_then_unit_conversion_and_suppression(tmp_path: Path, fmu_dir: Path) -> None:
    lin = '<ssc:LinearTransformation factor="2.0" offset="5.0"/>'
    xml = system_xml(gain("a", u_real=10.0, units=(None, "degC")) + gain("b", units=("K", None))
                     + gain("c", units=("K", None)),
                     connection("a.y_real", "b.u_real", lin) + connection("a.y_real", "c.u_real", lin, True))
    out = final(make(tmp_path, fmu_dir, xml), "b.u_real", "c.u_real")
    assert out["b.u_real"] == pytest.approx(2 * 10 + 5 + 273.15)  # transformed in degC, then converted to K
    assert out["c.u_real"] == pytest.approx(2 * 10 + 5)           # suppressUnitConversion: transformation only


def test_units_of_different_dimensions_are_refused(tmp_path: Path, fmu_dir: Path) -> None:
    xml = system_xml(gain("a", units=(None, "ft")) + gain("b", units=("K", None)), connection("a.y_real", "b.u_real"))
    with pytest.raises(SystemStructureError, match=r"cannot convert 'ft' \(m\) to 'K' \(K\)"):
        bind_system(load_system(make(tmp_path, fmu_dir, xml)))


def test_undefined_unit_is_refused(tmp_path: Path, fmu_dir: Path) -> None:
    xml = system_xml(gain("a", units=(None, "furlong")) + gain("b", units=("m", None)),
                     connection("a.y_real", "b.u_real"))
    with pytest.raises(SystemStructureError, match="unit 'furlong' is not defined"):
        bind_system(load_system(make(tmp_path, fmu_dir, xml)))


def test_boolean_and_integer_mapping_transformations(tmp_path: Path, fmu_dir: Path) -> None:
    bool_map = ('<ssc:BooleanMappingTransformation><ssc:MapEntry source="true" target="false"/>'
                '<ssc:MapEntry source="false" target="true"/></ssc:BooleanMappingTransformation>')
    int_map = ('<ssc:IntegerMappingTransformation><ssc:MapEntry source="1" target="10"/>'
               '<ssc:MapEntry source="2" target="20"/></ssc:IntegerMappingTransformation>')
    xml = system_xml(gain("a", u_int=0, u_bool=False) + gain("b"),
                     connection("a.y_bool", "b.u_bool", bool_map) + connection("a.y_int", "b.u_int", int_map))
    out = final(make(tmp_path, fmu_dir, xml), "a.y_bool", "b.u_bool", "a.y_int", "b.u_int", "b.y_int")
    assert out["a.y_bool"] == 1 and out["b.u_bool"] == 0   # not False = True, mapped to False
    assert out["a.y_int"] == 1 and out["b.u_int"] == 10 and out["b.y_int"] == 11


def test_linear_transformation_on_an_integer_connection_is_refused(tmp_path: Path, fmu_dir: Path) -> None:
    xml = system_xml(gain("a") + gain("b"),
                     connection("a.y_int", "b.u_int", '<ssc:LinearTransformation factor="2"/>'))
    with pytest.raises(SystemStructureError, match="LinearTransformation on a Integer connection"):
        bind_system(load_system(make(tmp_path, fmu_dir, xml)))


def _with_enumerations(fmu: Path, out: Path) -> Path:
    """Gain.fmu with u_int and y_int declared as enumerations (pythonfmu cannot declare them;
    FMI 2.0 exchanges enumerations through fmi2Get/SetInteger, so the FMU works unchanged)."""
    with zipfile.ZipFile(fmu) as zf:
        entries = {i.filename: zf.read(i.filename) for i in zf.infolist()}
    md = entries["modelDescription.xml"].decode()
    types = ('<TypeDefinitions>'
             '<SimpleType name="Gear"><Enumeration><Item name="up" value="1"/><Item name="down" value="2"/>'
             '</Enumeration></SimpleType>'
             '<SimpleType name="Lamp"><Enumeration><Item name="off" value="0"/><Item name="green" value="1"/>'
             '<Item name="red" value="5"/></Enumeration></SimpleType></TypeDefinitions>')
    md = md.replace("<ModelVariables>", types + "<ModelVariables>", 1)
    import re

    md = re.sub(r'(name="u_int"[^>]*>\s*)<Integer([^/]*)/>', r'\1<Enumeration declaredType="Lamp"\2/>', md)
    md = re.sub(r'(name="y_int"[^>]*>\s*)<Integer([^/]*)/>', r'\1<Enumeration declaredType="Gear"\2/>', md)
    entries["modelDescription.xml"] = md.encode()
    with zipfile.ZipFile(out, "w") as zf:
        for name, data in entries.items():
            zf.writestr(name, data)
    return out


def test_enumeration_mapping_transformation(tmp_path: Path, fmu_dir: Path) -> None:
    enum_map = ('<ssc:EnumerationMappingTransformation><ssc:MapEntry source="up" target="red"/>'
                '<ssc:MapEntry source="down" target="green"/></ssc:EnumerationMappingTransformation>')
    enumerations = ('<ssd:Enumerations>'
                    '<ssc:Enumeration name="Gear"><ssc:Item name="up" value="1"/><ssc:Item name="down" value="2"/>'
                    '</ssc:Enumeration>'
                    '<ssc:Enumeration name="Lamp"><ssc:Item name="off" value="0"/><ssc:Item name="green" value="1"/>'
                    '<ssc:Item name="red" value="5"/></ssc:Enumeration></ssd:Enumerations>')
    xml = system_xml(gain("a", u_int=0) + gain("b"), connection("a.y_int", "b.u_int", enum_map),
                     enumerations=enumerations)
    xml = xml.replace('<ssd:Connector name="u_int" kind="input"><ssc:Integer/>',
                      '<ssd:Connector name="u_int" kind="input"><ssc:Enumeration name="Lamp"/>')
    xml = xml.replace('<ssd:Connector name="y_int" kind="output"><ssc:Integer/>',
                      '<ssd:Connector name="y_int" kind="output"><ssc:Enumeration name="Gear"/>')
    folder = make(tmp_path, fmu_dir, xml)
    _with_enumerations(fmu_dir / "Gain.fmu", folder / "resources" / "Gain.fmu")
    out = final(folder, "a.y_int", "b.u_int")
    assert out["a.y_int"] == 1 and out["b.u_int"] == 5  # Gear 'up' (1) mapped to Lamp 'red' (5)
    bad = xml.replace('target="red"', 'target="blue"')
    (folder / "SystemStructure.ssd").write_text(bad)
    with pytest.raises(SystemStructureError, match="'blue' is not an item of the enumeration"):
        bind_system(load_system(folder))
    # the SSD's declaration of an enumeration must agree with the FMU's
    (folder / "SystemStructure.ssd").write_text(xml.replace('<ssc:Item name="red" value="5"/>',
                                                            '<ssc:Item name="red" value="4"/>'))
    with pytest.raises(SystemStructureError, match="enumeration 'Lamp' of the SSD differs from the FMU's"):
        bind_system(load_system(folder))


# -- structure -------------------------------------------------------------------------------------
def test_nested_systems_are_flattened_through_their_connectors(tmp_path: Path, fmu_dir: Path) -> None:
    inner = f"""<ssd:System name="S">
  <ssd:Connectors>
    <ssd:Connector name="in_ft" kind="input"><ssc:Real unit="ft"/></ssd:Connector>
    <ssd:Connector name="out_m" kind="output"><ssc:Real unit="m"/></ssd:Connector>
  </ssd:Connectors>
  <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
    <ssv:ParameterSet version="1.0" name="s"><ssv:Parameters>
      <ssv:Parameter name="b.k"><ssv:Real value="2.0"/></ssv:Parameter>
    </ssv:Parameters></ssv:ParameterSet>
  </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
  <ssd:Elements>{gain("b", units=("m", "m"))}</ssd:Elements>
  <ssd:Connections>
    {connection("in_ft", "b.u_real", '<ssc:LinearTransformation factor="1.0" offset="10.0"/>')}
    {connection("b.y_real", "out_m")}
  </ssd:Connections>
</ssd:System>"""
    xml = system_xml(gain("a", u_real=100.0, units=(None, "ft")) + inner + gain("c", units=("ft", None)),
                     connection("a.y_real", "S.in_ft") + connection("S.out_m", "c.u_real"))
    folder = make(tmp_path, fmu_dir, xml)
    bound = bind_system(load_system(folder))
    assert [c.name for c in bound.components] == ["a", "c", "S.b"]
    out = final(folder, "S.b.u_real", "S.b.y_real", "c.u_real")
    # 100 ft + 10 ft (transformation inside S, in ft) = 110 ft = 33.528 m into b; b doubles (k from S's binding)
    assert out["S.b.u_real"] == pytest.approx(33.528)
    assert out["S.b.y_real"] == pytest.approx(67.056)
    assert out["c.u_real"] == pytest.approx(67.056 / 0.3048)  # back to ft for c


def test_signal_dictionary_carries_a_signal_across_systems(tmp_path: Path, fmu_dir: Path) -> None:
    dictionary = ('<ssd:SignalDictionaries><ssd:SignalDictionary name="bus" source="bus.ssb"/>'
                  '</ssd:SignalDictionaries>')
    ssb = ('<?xml version="1.0" encoding="UTF-8"?>\n'
           '<ssb:SignalDictionary xmlns:ssb="http://ssp-standard.org/SSP1/SystemStructureSignalDictionary" '
           'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0">'
           '<ssb:DictionaryEntry name="speed"><ssc:Real unit="kn"/></ssb:DictionaryEntry>'
           '<ssb:Units><ssc:Unit name="kn"><ssc:BaseUnit m="1" s="-1" factor="0.5144444444444445"/></ssc:Unit>'
           '</ssb:Units></ssb:SignalDictionary>\n')
    ref_out = ('<ssd:SignalDictionaryReference name="busw" dictionary="bus"><ssd:Connectors>'
               '<ssd:Connector name="speed" kind="input"><ssc:Real unit="kn"/></ssd:Connector>'
               '</ssd:Connectors></ssd:SignalDictionaryReference>')
    ref_in = ('<ssd:SignalDictionaryReference name="busr" dictionary="bus"><ssd:Connectors>'
              '<ssd:Connector name="speed" kind="output"><ssc:Real unit="kn"/></ssd:Connector>'
              '</ssd:Connectors></ssd:SignalDictionaryReference>')
    inner = (f'<ssd:System name="S"><ssd:Elements>{gain("b", units=("m/s", None))}{ref_in}</ssd:Elements>'
             f'<ssd:Connections>{connection("busr.speed", "b.u_real")}</ssd:Connections></ssd:System>')
    units = UNITS.replace('<ssc:Unit name="kn"><ssc:BaseUnit m="1" s="-1" factor="0.5144444444444445"/></ssc:Unit>',
                          "")  # knots are defined by the dictionary's own Units here
    xml = system_xml(gain("a", u_real=100.0, units=(None, "kn")) + ref_out + inner,
                     connection("a.y_real", "busw.speed"), extra=dictionary, units=units)
    out = final(make(tmp_path, fmu_dir, xml, {"bus.ssb": ssb}), "S.b.u_real")
    assert out["S.b.u_real"] == pytest.approx(51.44444444444445)  # 100 kn in m/s


# -- parameters ------------------------------------------------------------------------------------
SSV = ('<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet '
       'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" '
       'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0" name="p">'
       '<ssv:Parameters>{}</ssv:Parameters>{}</ssv:ParameterSet>\n')
SSM = ('<?xml version="1.0" encoding="UTF-8"?>\n<ssm:ParameterMapping '
       'xmlns:ssm="http://ssp-standard.org/SSP1/SystemStructureParameterMapping" '
       'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0">{}</ssm:ParameterMapping>\n')


def test_parameter_mapping_file_renames_and_transforms(tmp_path: Path, fmu_dir: Path) -> None:
    ssv = SSV.format('<ssv:Parameter name="gain_percent"><ssv:Real value="250"/></ssv:Parameter>'
                     '<ssv:Parameter name="u_real"><ssv:Real value="4"/></ssv:Parameter>', "")
    ssm = SSM.format('<ssm:MappingEntry source="gain_percent" target="k">'
                     '<ssc:LinearTransformation factor="0.01"/></ssm:MappingEntry>')
    comp = gain("a").replace(
        '<ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>',
        '<ssd:ParameterBindings><ssd:ParameterBinding source="a.ssv"><ssd:ParameterMapping source="a.ssm"/>'
        '</ssd:ParameterBinding><ssd:ParameterBinding><ssd:ParameterValues>')
    comp = comp.replace('<ssv:Parameter name="k"><ssv:Real value="1.0"/></ssv:Parameter>', "")
    xml = system_xml(comp, "")
    out = final(make(tmp_path, fmu_dir, xml, {"a.ssv": ssv, "a.ssm": ssm}), "a.y_real")
    assert out["a.y_real"] == pytest.approx(2.5 * 4)


def test_parameter_value_in_other_units_is_converted(tmp_path: Path, fmu_dir: Path) -> None:
    ssv = SSV.format('<ssv:Parameter name="a.u_real"><ssv:Real value="77" unit="degF"/></ssv:Parameter>',
                     '<ssv:Units><ssc:Unit name="degF"><ssc:BaseUnit K="1" factor="0.5555555555555556" '
                     'offset="255.3722222222222"/></ssc:Unit></ssv:Units>')
    xml = system_xml(gain("a", units=("degC", None)), "",
                     bindings='<ssd:ParameterBindings><ssd:ParameterBinding source="p.ssv"/></ssd:ParameterBindings>')
    out = final(make(tmp_path, fmu_dir, xml, {"p.ssv": ssv}), "a.u_real")
    assert out["a.u_real"] == pytest.approx(25.0)  # 77 degF = 25 degC


# -- what we do not apply is an error with its line ---------------------------------------------------
def test_unapplied_elements_are_reported_with_their_line(tmp_path: Path, fmu_dir: Path) -> None:
    xml = system_xml(gain("a"), "", bindings=('<ssd:ParameterBindings>'
                                               '<ssd:ParameterBinding source="p.ssv" sourceBase="component"/>'
                                               '</ssd:ParameterBindings>'))
    folder = make(tmp_path, fmu_dir, xml, {"p.ssv": SSV.format("", "")})
    with pytest.raises(SystemStructureError, match=r"SystemStructure.ssd:\d+: sourceBase 'component' is not "):
        load_system(folder)
