for (const [id, spec] of causticbenchPlots) {
  const element = document.getElementById(id);
  const fail = (text) => {
    const message = document.createElement("p");
    message.className = "plot-error";
    message.textContent = "Plot not drawn: " + text;
    element.replaceChildren(message);
  };
  if (typeof vegaEmbed === "undefined") {
    fail("report/vendor/vega*.min.js did not load");
    continue;
  }
  vegaEmbed(element, spec, {renderer: "svg", actions: false}).catch((failure) => fail(String(failure)));
}
