//! A small reader of delimited text tables (RFC 4180 CSV as spreadsheets and GIS export it):
//! a header row, then one record per line; fields separated by `,`, `;` or tabs (whichever the
//! header uses), optionally quoted with `"` (a doubled `""` inside quotes is one quote). A byte
//! order mark, blank lines and lines starting with `#` are skipped. Quoted fields may not span
//! lines (field tables never need it, and it keeps every record on its own line number).

/// One record: its 1-based line in the file and its fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub line: usize,
    pub fields: Vec<String>,
}

/// A parsed table.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub header: Vec<String>,
    pub records: Vec<Record>,
}

impl Table {
    /// Parses `text`; errors name the line.
    pub fn parse(text: &str) -> Result<Table, String> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
            .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
        let (header_line, header) = lines.next().ok_or("is empty: it needs a header row")?;
        let delimiter = [';', '\t', ','].into_iter().find(|d| header.contains(*d)).unwrap_or(',');
        let header: Vec<String> = split(header, delimiter)
            .map_err(|e| format!("{header_line}: {e}"))?
            .into_iter()
            .map(|h| h.trim().to_string())
            .collect();
        let mut records = Vec::new();
        for (line, text) in lines {
            let fields = split(text, delimiter).map_err(|e| format!("{line}: {e}"))?;
            if fields.len() != header.len() {
                return Err(format!("{line}: has {} fields, the header {}", fields.len(), header.len()));
            }
            records.push(Record { line, fields });
        }
        Ok(Table { header, records })
    }

    /// The index of the column named `name` (case and surrounding spaces ignored).
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h.eq_ignore_ascii_case(name.trim()))
    }
}

/// The fields of one line.
fn split(line: &str, delimiter: char) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut was_quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') if field.trim().is_empty() && !was_quoted => {
                field.clear();
                quoted = true;
                was_quoted = true;
            }
            (false, c) if c == delimiter => {
                fields.push(finish(&field, was_quoted));
                field.clear();
                was_quoted = false;
            }
            (false, c) => field.push(c),
        }
    }
    if quoted {
        return Err("a quoted field is not closed".into());
    }
    fields.push(finish(&field, was_quoted));
    Ok(fields)
}

fn finish(field: &str, quoted: bool) -> String {
    if quoted { field.to_string() } else { field.trim().to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_quotes_delimiters_and_line_numbers() {
        let text = "\u{feff}name;X;Y\r\n# comment\n\n\"Gouffre; \"\"A\"\"\";651234.5; 6862345\nB;1;2\n";
        let t = Table::parse(text).unwrap();
        assert_eq!(t.header, ["name", "X", "Y"]);
        assert_eq!(
            t.records[0],
            Record { line: 4, fields: vec!["Gouffre; \"A\"".into(), "651234.5".into(), "6862345".into()] }
        );
        assert_eq!(t.records[1].line, 5);
        assert_eq!(t.column("x"), Some(1));
        assert_eq!(Table::parse("a,b\n1,2\n").unwrap().records[0].fields, ["1", "2"]);
        assert_eq!(Table::parse("a\tb\n1\t2\n").unwrap().records[0].fields, ["1", "2"]);
    }

    #[test]
    fn ragged_rows_and_open_quotes_name_their_line() {
        assert_eq!(Table::parse("a,b\n1,2\n3\n").unwrap_err(), "3: has 1 fields, the header 2");
        assert_eq!(Table::parse("a,b\n\"1,2\n").unwrap_err(), "2: a quoted field is not closed");
        assert!(Table::parse("\n# only a comment\n").unwrap_err().contains("is empty"));
    }
}
